#!/usr/bin/env python3
"""The folder layers of lib/: who includes whom.

  scripts/layers.py --check     fail (exit 1) when a folder includes one of a higher layer, or one not listed, or
                                when two headers under lib/ share a file name
  scripts/layers.py --dot       print the include graph between folders as Graphviz (docs/layers.svg:
                                scripts/layers.py --dot | dot -Tsvg -o docs/layers.svg)
"""
import os
import re
import sys

# Lowest first; a folder may include its own layer's headers and any lower layer's, never a higher one's.
LAYERS = [
    ["util"],
    ["scene", "grid", "image", "gpu"],
    ["bvh", "metrics"],
    ["reference"],
    ["sdf"],
    ["render"],
    ["jobs"],
    ["bench", "view"],
]
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lib")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([A-Za-z_]+)/')


def edges():
    """(from folder, to folder) -> first 'file:line' that makes the edge."""
    found = {}
    for folder in sorted(os.listdir(ROOT)):
        if not os.path.isdir(os.path.join(ROOT, folder)):
            continue
        for dirpath, _, files in os.walk(os.path.join(ROOT, folder)):
            for name in sorted(files):
                if not name.endswith((".h", ".cpp")):
                    continue
                path = os.path.join(dirpath, name)
                with open(path, errors="ignore") as f:
                    for number, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if m and m.group(1) != folder and os.path.isdir(os.path.join(ROOT, m.group(1))):
                            found.setdefault((folder, m.group(1)), f"{os.path.relpath(path, ROOT)}:{number}")
    return found


def layer_of(folder):
    for i, layer in enumerate(LAYERS):
        if folder in layer:
            return i
    return None


def same_named_headers():
    """Headers under lib/ whose file name another header has too: 'name: path, path'. A subfolder is a stage of its
    top folder, and names must say which ("CoarseParams.h", not a second "CoarseSdf.h")."""
    paths = {}
    for dirpath, _, files in os.walk(ROOT):
        for name in files:
            if name.endswith(".h"):
                paths.setdefault(name, []).append(os.path.relpath(os.path.join(dirpath, name), ROOT))
    return [f"{name}: {', '.join(sorted(p))}" for name, p in sorted(paths.items()) if len(p) > 1]


def check():
    problems = []
    folders = {f for f in os.listdir(ROOT) if os.path.isdir(os.path.join(ROOT, f))}
    for f in sorted(folders):
        if layer_of(f) is None:
            problems.append(f"lib/{f}: not in any layer of scripts/layers.py")
    for (a, b), where in sorted(edges().items()):
        la, lb = layer_of(a), layer_of(b)
        if la is not None and lb is not None and lb > la:
            problems.append(f"lib/{where}: {a} (layer {la}) includes {b} (layer {lb}), a higher layer")
    for clash in same_named_headers():
        problems.append(f"two headers under lib/ share a file name: {clash}")
    for p in problems:
        print(p)
    print(f"{len(folders)} folders in {len(LAYERS)} layers: "
          f"{'no upward include, no two headers of one name' if not problems else 'FAILED'}")
    return 1 if problems else 0


def dot():
    print("digraph layers {")
    print('  rankdir=BT; node [shape=box, fontname="Helvetica"]; edge [color="#777777"];')
    for i, layer in enumerate(LAYERS):
        print(f"  {{ rank=same; {'; '.join(layer)}; }}")
    print('  apps [label="apps/rtsdf", style=dashed];')
    apps = os.path.join(ROOT, "..", "apps", "rtsdf")
    used = set()
    for name in sorted(os.listdir(apps)):
        with open(os.path.join(apps, name), errors="ignore") as f:
            used |= {m.group(1) for m in map(INCLUDE.match, f) if m}
    for b in sorted(used & {f for layer in LAYERS for f in layer}):
        print(f"  apps -> {b};")
    for (a, b) in sorted(edges()):
        print(f"  {a} -> {b};")
    print("}")
    return 0


if __name__ == "__main__":
    if sys.argv[1:] == ["--check"]:
        sys.exit(check())
    if sys.argv[1:] == ["--dot"]:
        sys.exit(dot())
    print(__doc__)
    sys.exit(2)
