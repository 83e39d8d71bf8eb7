#!/usr/bin/env python3
"""The README's library snippet is a real program (examples/readme/library_snippet.cpp).

  scripts/check_readme_snippet.py --text              fail unless the README's C++ block under "Using the library"
                                                      equals the file's README-SNIPPET blocks (each unindented,
                                                      joined by an empty line)
  scripts/check_readme_snippet.py --run SNIPPET RTSDF  run the built snippet in a scratch folder holding the data
                                                      (its scene path is relative), print its wall time, and check
                                                      its out.vdb against `rtsdf bake` with the same settings
                                                      (`rtsdf compare`: no difference)
"""
import os
import re
import subprocess
import sys
import tempfile
import textwrap
import time

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
SNIPPET = os.path.join(ROOT, "examples", "readme", "library_snippet.cpp")


def readme_block():
    text = open(os.path.join(ROOT, "README.md")).read()
    section = text[text.index("## Using the library"):]
    return re.search(r"```cpp\n(.*?)```", section, re.S).group(1).rstrip("\n")


def file_blocks():
    text = open(SNIPPET).read()
    blocks = re.findall(r"^[ \t]*// README-SNIPPET-BEGIN\n(.*?)^[ \t]*// README-SNIPPET-END\n", text, re.S | re.M)
    return "\n\n".join(textwrap.dedent(b).rstrip("\n") for b in blocks)


def check_text():
    readme, snippet = readme_block(), file_blocks()
    if readme != snippet:
        import difflib
        sys.stdout.writelines(difflib.unified_diff(readme.splitlines(True), snippet.splitlines(True), "README.md",
                                                   os.path.relpath(SNIPPET, ROOT)))
        print("\nthe README's library snippet differs from examples/readme/library_snippet.cpp")
        return 1
    print("the README's library snippet is examples/readme/library_snippet.cpp")
    return 0


def run(snippet, rtsdf):
    with tempfile.TemporaryDirectory(prefix="rtsdf-snippet-") as work:
        os.symlink(os.path.join(ROOT, "data"), os.path.join(work, "data"))
        start = time.perf_counter()
        done = subprocess.run([snippet], cwd=work, capture_output=True, text=True)
        seconds = time.perf_counter() - start
        print(done.stdout + done.stderr, end="")
        if done.returncode != 0:
            print(f"the snippet failed (exit {done.returncode})")
            return 1
        print(f"the README's library snippet ran in {seconds:.1f} s (wall)")
        cli = [rtsdf, "-q", "bake", "data/scenes/default.json", "-m", "rtsdf", "--res", "128", "--band", "6vox",
               "-o", "cli.vdb"]
        subprocess.run(cli, cwd=work, check=True, capture_output=True)
        compared = subprocess.run([rtsdf, "-q", "compare", "out.vdb", "cli.vdb"], cwd=work, capture_output=True,
                                  text=True, check=True).stdout
        print(compared, end="")
        if "(0 only in A, 0 only in B)" not in compared or "max 0.0000 voxels" not in compared:
            print("the snippet's out.vdb differs from `rtsdf bake ... -m rtsdf --res 128`")
            return 1
    return 0


if __name__ == "__main__":
    if sys.argv[1:] == ["--text"]:
        sys.exit(check_text())
    if len(sys.argv) == 4 and sys.argv[1] == "--run":
        sys.exit(run(sys.argv[2], sys.argv[3]))
    print(__doc__)
    sys.exit(2)
