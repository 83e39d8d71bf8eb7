#!/usr/bin/env python3
"""Write the bad-input table of docs/reliability.md from tests/cli/bad_inputs.json (the rows the test runs).
Usage: scripts/reliability_table.py [--check]   (--check: fail when the document's table is out of date)"""
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
TABLE = ROOT / "tests/cli/bad_inputs.json"
DOC = ROOT / "docs/reliability.md"
BEGIN, END = "<!-- table:begin -->", "<!-- table:end -->"


def describe(name, spec):
    if isinstance(spec, str):
        return f"`{name}`"
    for key, what in (("fifo", "FIFO"), ("folder", "folder"), ("hex", "bytes"), ("regression", "fuzz input")):
        if key in spec:
            return f"`{name}` ({what})"
    if "bytes" in spec:
        return f"`{name}` (first {spec['bytes']} bytes of {spec.get('fixture', spec.get('data'))})"
    return f"`{name}`"


def table():
    rows = json.loads(TABLE.read_text())["rows"]
    out = ["| kind | files | command | exit | the message holds |", "| --- | --- | --- | --- | --- |"]
    for r in rows:
        files = ", ".join(describe(k, v) for k, v in r.get("files", {}).items()) or "-"
        command = " ".join(a if a else '""' for a in ["rtsdf"] + r["args"])
        words = "; ".join(w.replace("|", "\\|") for w in r.get("words", []))
        out.append(f"| {r['kind']} | {files} | `{command}` | {r['exit']} | {words} |")
    return "\n".join(out)


def main():
    doc = DOC.read_text()
    head, rest = doc.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    new = f"{head}{BEGIN}\n{table()}\n{END}{tail}"
    if "--check" in sys.argv:
        if new != doc:
            sys.exit(f"{DOC}: the bad-input table is out of date: run scripts/reliability_table.py")
        return
    DOC.write_text(new)


if __name__ == "__main__":
    main()
