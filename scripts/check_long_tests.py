#!/usr/bin/env python3
"""Check that every test tests/long_tests.cmake labels `long` is a test ctest lists, and carries the label: ctest's
set_tests_properties passes over a name no test has without a word, so a renamed or misspelt test would silently
lose the label and run under CI's sanitizers again.
Usage: scripts/check_long_tests.py BUILD_DIR
       scripts/check_long_tests.py --self-test   (a made-up list with a missing name must be reported)"""
import json
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
LIST = ROOT / "tests/long_tests.cmake"
NAME = re.compile(r"\b([A-Z]\w*\.[A-Z]\w*)\b")


def listed_names(text):
    """The test names (Suite.Test) the file's set_tests_properties calls name, comments left out."""
    names = []
    for line in text.splitlines():
        code = line.split("#", 1)[0]
        names += NAME.findall(code)
    return names


def problems(names, labels_of):
    """One line per name that is no test or lacks the label `long`; @a labels_of maps test names to labels."""
    out = []
    for name in names:
        if name not in labels_of:
            out.append(f"{LIST.relative_to(ROOT)}: `{name}` is no test ctest lists")
        elif "long" not in labels_of[name]:
            out.append(f"{LIST.relative_to(ROOT)}: `{name}` has no label long")
    return out


def ctest_labels(build):
    shown = subprocess.run(["ctest", "--show-only=json-v1"], cwd=build, check=True, capture_output=True, text=True)
    labels = {}
    for test in json.loads(shown.stdout)["tests"]:
        props = {p["name"]: p["value"] for p in test.get("properties", [])}
        labels[test["name"]] = props.get("LABELS", [])
    return labels


def self_test():
    names = listed_names("set_tests_properties(\n  A.Real # B.Commented\n  C.Missing\n  PROPERTIES LABELS long)\n")
    assert names == ["A.Real", "C.Missing"], names
    found = problems(names, {"A.Real": ["gpu", "long"]})
    assert len(found) == 1 and "C.Missing" in found[0], found
    assert problems(["A.Real"], {"A.Real": ["gpu"]}), "a test without the label must be reported"
    print("check_long_tests: the self-test found the missing name and the missing label")


def main():
    if sys.argv[1:] == ["--self-test"]:
        self_test()
        return 0
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    names = listed_names(LIST.read_text())
    found = problems(names, ctest_labels(sys.argv[1]))
    for line in found:
        print(line)
    if not found:
        print(f"{LIST.relative_to(ROOT)}: {len(names)} long tests, each listed by ctest with the label")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
