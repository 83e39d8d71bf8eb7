#!/usr/bin/env python3
"""The folder layers of lib/ and the front ends over them: who includes whom, whose detail:: names are used where.

  scripts/layers.py --check      fail (exit 1) when a folder includes one of a higher layer, or one not listed, or
                                 uses a detail:: name another folder declares, or when two headers under lib/ share
                                 a file name
  scripts/layers.py --self-test  run --check's rules on small made-up trees, one per rule, and fail unless each
                                 breach is reported and the clean tree passes
  scripts/layers.py --dot        print the include graph between folders as Graphviz (docs/layers.svg:
                                 scripts/layers.py --dot | tred | dot -Tsvg -o docs/layers.svg)
"""
import os
import re
import sys
import tempfile

# Lowest first; a folder may include its own layer's headers and any lower layer's, never a higher one's.
LAYERS = [
    ["util"],
    ["scene", "grid", "image", "gpu"],
    ["bvh", "metrics"],
    ["reference"],
    ["sdf"],
    ["render"],
    ["jobs"],
    ["suites", "view"],
]
# The front ends, one layer over every folder of lib/ (paths from the repository's root): they bind the jobs.
FRONT_ENDS = ["apps/rtsdf", "python"]
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lib")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([A-Za-z_]+)/')
SOURCE_SUFFIXES = (".h", ".cpp")


def edges(root=ROOT):
    """(from folder, to folder) -> first 'file:line' that makes the edge."""
    found = {}
    for folder in sorted(os.listdir(root)):
        if not os.path.isdir(os.path.join(root, folder)):
            continue
        for dirpath, _, files in os.walk(os.path.join(root, folder)):
            for name in sorted(files):
                if not name.endswith(SOURCE_SUFFIXES):
                    continue
                path = os.path.join(dirpath, name)
                with open(path, errors="ignore") as f:
                    for number, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if m and m.group(1) != folder and os.path.isdir(os.path.join(root, m.group(1))):
                            found.setdefault((folder, m.group(1)), f"{os.path.relpath(path, root)}:{number}")
    return found


def layer_of(folder, layers=None):
    for i, layer in enumerate(layers or LAYERS):
        if folder in layer:
            return i
    return None


def same_named_headers(root=ROOT):
    """Headers under lib/ whose file name another header has too: 'name: path, path'. A subfolder is a stage of its
    top folder, and names must say which ("CoarseParams.h", not a second "CoarseSdf.h")."""
    paths = {}
    for dirpath, _, files in os.walk(root):
        for name in files:
            if name.endswith(".h"):
                paths.setdefault(name, []).append(os.path.relpath(os.path.join(dirpath, name), root))
    return [f"{name}: {', '.join(sorted(p))}" for name, p in sorted(paths.items()) if len(p) > 1]



# --- The front ends: apps/rtsdf and python sit over lib/ -------------------------------------------------------


def units(root=ROOT, front_ends=FRONT_ENDS):
    """Each unit the rules speak of -> its source files: every folder of lib/ ('gpu'), every front end ('python')."""
    found = {}
    top = os.path.dirname(os.path.abspath(root))
    places = [(f, os.path.join(root, f)) for f in sorted(os.listdir(root)) if os.path.isdir(os.path.join(root, f))]
    places += [(f, os.path.join(top, f)) for f in front_ends if os.path.isdir(os.path.join(top, f))]
    for unit, where in places:
        files = []
        for dirpath, _, names in os.walk(where):
            files += [os.path.join(dirpath, n) for n in sorted(names) if n.endswith(SOURCE_SUFFIXES)]
        found[unit] = files
    return found


def front_end_problems(root=ROOT, front_ends=FRONT_ENDS):
    """A folder of lib/ that includes a front end's file: lib/ is below apps/ and python/, never beside them."""
    problems = []
    top = os.path.dirname(os.path.abspath(root))
    roots = {f.split("/")[0] for f in front_ends}
    for unit, files in units(root, []).items():
        for path in files:
            with open(path, errors="ignore") as f:
                for number, line in enumerate(f, 1):
                    m = INCLUDE.match(line)
                    if m and m.group(1) in roots:
                        problems.append(f"{os.path.relpath(path, top)}:{number}: {unit} (lib/) includes "
                                        f"{m.group(1)}/, a front end over every layer")
    return problems


# --- detail:: names stay in the folder that declares them -------------------------------------------------------

COMMENT_OR_STRING = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)
DETAIL_NAMESPACE = re.compile(r"\bnamespace\s+(?:\w+\s*::\s*)*detail\s*\{")
# A use: detail::name, unqualified or under one of our namespaces (fmt::detail:: and the like are not ours).
DETAIL_USE = re.compile(r"(?<![\w:])((?:\w+::)*)detail::(\w+)")
USING_DETAIL = re.compile(r"\busing\s+namespace\s+(?:\w+::)*detail\s*;")
FOREIGN = {"std", "fmt", "spdlog", "nlohmann", "pybind11", "py", "CLI", "openvdb", "glm", "tbb", "Imath", "vk",
           "testing", "boost"}
KEYWORDS = {"if", "for", "while", "switch", "return", "sizeof", "alignof", "decltype", "static_assert", "operator",
            "void", "int", "bool", "float", "double", "char", "auto", "const", "constexpr", "inline", "static",
            "extern", "template", "typename", "noexcept", "explicit", "unsigned", "signed", "long", "short"}


def blank_comments_and_strings(text):
    """@a text with comments and literals turned to spaces (newlines kept, so that line numbers hold)."""
    return COMMENT_OR_STRING.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def declared_detail_names(text):
    """The names a file declares at the top of its detail namespaces: functions, types, variables, aliases."""
    code = blank_comments_and_strings(text)
    names = set()
    for m in DETAIL_NAMESPACE.finditer(code):
        braces, i = 1, m.end()
        start = i
        while i < len(code) and braces:
            braces += (code[i] == "{") - (code[i] == "}")
            i += 1
        body = code[start:i - 1]
        # Keep only what lies at the namespace's own level: no function bodies, initialisers or parameter lists.
        top, depth = [], 0
        for c in body:
            if c in "({[":
                depth += 1
                top.append(c if depth == 1 else " ")
            elif c in ")}]":
                top.append(c if depth == 1 else " ")
                depth -= 1
            else:
                top.append(c if depth == 0 else " ")
        top = "".join(top)
        names |= set(re.findall(r"\b(?:struct|class|union|enum(?:\s+class)?|using)\s+(\w+)", top))
        names |= {n for n in re.findall(r"\b(\w+)\s*[(=;\[{]", top) if n not in KEYWORDS}
    return names


def detail_problems(root=ROOT, front_ends=FRONT_ENDS):
    """A detail:: name used outside the folder whose headers declare it (jobs' detail:: is the jobs' own)."""
    top = os.path.dirname(os.path.abspath(root))
    files = units(root, front_ends)
    texts = {p: open(p, errors="ignore").read() for fs in files.values() for p in fs}
    own = {u: set().union(*(declared_detail_names(texts[p]) for p in fs)) if fs else set() for u, fs in files.items()}
    declared_by = {}  # name -> (unit, header) for names declared in a header
    for unit, fs in files.items():
        for p in fs:
            if p.endswith(".h"):
                for n in declared_detail_names(texts[p]):
                    declared_by.setdefault(n, (unit, os.path.relpath(p, top)))
    problems = []
    for unit, fs in files.items():
        for p in fs:
            code = blank_comments_and_strings(texts[p])
            where = os.path.relpath(p, top)
            for m in DETAIL_USE.finditer(code):
                chain, name = m.group(1).split("::")[0], m.group(2)
                if chain in FOREIGN or name in own[unit] or name not in declared_by:
                    continue
                line = code.count("\n", 0, m.start()) + 1
                owner, header = declared_by[name]
                problems.append(f"{where}:{line}: {unit} uses detail::{name} of {owner} ({header}); "
                                f"make it public API of {owner} or keep it inside {owner}")
            for m in USING_DETAIL.finditer(code):
                if any(u != unit for u, _ in declared_by.values()):
                    line = code.count("\n", 0, m.start()) + 1
                    problems.append(f"{where}:{line}: {unit} brings in a detail namespace with 'using namespace'")
    return problems


def check(root=ROOT, layers=None, front_ends=FRONT_ENDS, quiet=False):
    layers = layers or LAYERS
    problems = []
    folders = {f for f in os.listdir(root) if os.path.isdir(os.path.join(root, f))}
    for f in sorted(folders):
        if layer_of(f, layers) is None:
            problems.append(f"lib/{f}: not in any layer of scripts/layers.py")
    for (a, b), where in sorted(edges(root).items()):
        la, lb = layer_of(a, layers), layer_of(b, layers)
        if la is not None and lb is not None and lb > la:
            problems.append(f"lib/{where}: {a} (layer {la}) includes {b} (layer {lb}), a higher layer")
    problems += front_end_problems(root, front_ends)
    problems += detail_problems(root, front_ends)
    problems += [f"two headers under lib/ share a file name: {clash}" for clash in same_named_headers(root)]
    if not quiet:
        for p in problems:
            print(p)
        print(f"{len(folders)} folders in {len(layers)} layers, {' and '.join(front_ends)} over them: "
              f"{'no upward include, no foreign detail::, no two headers of one name' if not problems else 'FAILED'}")
    return problems


# --- --self-test: each rule shown to fail on a tree made to break it --------------------------------------------

SELF_TEST_TREE = {
    "lib/low/Low.h": "#pragma once\nnamespace rtsdf::detail {\nint helper(int x);\n"
                     "inline int other() { return helper(1); }\n} // namespace rtsdf::detail\n"
                     "namespace rtsdf { int lowApi(); }\n",
    "lib/low/Low.cpp": '#include "low/Low.h"\nnamespace rtsdf::detail {\nint helper(int x) { return x; }\n}\n'
                       "namespace rtsdf { int lowApi() { return detail::helper(2); } }\n",
    "lib/high/High.cpp": '#include "low/Low.h"\n// detail::helper in a comment is no use\n'
                         'namespace rtsdf { int highApi() { return lowApi() + fmt::detail::count(); } }\n',
    "python/module.cpp": '#include "high/High.h"\nint f() { return rtsdf::lowApi(); }\n',
    "apps/rtsdf/main.cpp": '#include "low/Low.h"\n#include "Options.h"\nint main() { return rtsdf::lowApi(); }\n',
}
SELF_TEST_LAYERS = [["low"], ["high"]]
# Each breach: the file it adds or replaces, its text, and a piece of the message --check must print.
SELF_TEST_BREACHES = [
    ("lib/low/Up.cpp", '#include "high/High.h"\n', "low (layer 0) includes high (layer 1)"),
    ("lib/stray/Stray.h", "#pragma once\n", "lib/stray: not in any layer"),
    ("lib/high/High.cpp", '#include "low/Low.h"\nint g() { return rtsdf::detail::helper(3); }\n',
     "high uses detail::helper of low (lib/low/Low.h)"),
    ("python/module.cpp", '#include "low/Low.h"\nint f() { return rtsdf::detail::other(); }\n',
     "python uses detail::other of low"),
    ("apps/rtsdf/main.cpp", '#include "low/Low.h"\nusing namespace rtsdf::detail;\nint main() { return 0; }\n',
     "apps/rtsdf brings in a detail namespace"),
    ("lib/low/Back.cpp", '#include "python/module.h"\n', "low (lib/) includes python/"),
    ("lib/high/Low.h", "#pragma once\n", "two headers under lib/ share a file name: Low.h"),
]


def self_test():
    def make(base, tree):
        for rel, text in tree.items():
            os.makedirs(os.path.dirname(os.path.join(base, rel)), exist_ok=True)
            with open(os.path.join(base, rel), "w") as f:
                f.write(text)

    failures = []
    with tempfile.TemporaryDirectory() as base:
        make(base, SELF_TEST_TREE)
        clean = check(os.path.join(base, "lib"), SELF_TEST_LAYERS, quiet=True)
        if clean:
            failures.append(f"the clean tree fails: {clean}")
    for rel, text, expected in SELF_TEST_BREACHES:
        with tempfile.TemporaryDirectory() as base:
            make(base, {**SELF_TEST_TREE, rel: text})
            found = check(os.path.join(base, "lib"), SELF_TEST_LAYERS, quiet=True)
            if not any(expected in p for p in found):
                failures.append(f"{rel}: expected '{expected}', --check printed {found}")
            elif len(found) != 1:
                failures.append(f"{rel}: one problem expected, --check printed {found}")
    for f in failures:
        print(f)
    print(f"{len(SELF_TEST_BREACHES)} breaches and a clean tree: {'each reported' if not failures else 'FAILED'}")
    return 1 if failures else 0


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
        sys.exit(1 if check() else 0)
    if sys.argv[1:] == ["--self-test"]:
        sys.exit(self_test())
    if sys.argv[1:] == ["--dot"]:
        sys.exit(dot())
    print(__doc__)
    sys.exit(2)
