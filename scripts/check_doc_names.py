#!/usr/bin/env python3
"""Every code name and file a document cites exists in the source tree.

  scripts/check_doc_names.py [DOC ...]   check DOC (default docs/design.md; paths from the repository's root) and
                                         fail (exit 1) listing each name or path that is not in the tree
  scripts/check_doc_names.py --self-test check a made-up tree and document: each kind of stale citation must be
                                         reported and the current ones must pass

What counts as cited:
  - a file path, in backticks or not: lib/..., shaders/..., apps/..., tests/... (also python/, scripts/, cmake/,
    bench/, fuzz/, examples/, docs/, data/, and paths inside lib/ such as gpu/shared/Refine.h). A path may name a
    file, a folder, a file without its extension (lib/sdf/SdfPipeline: its .h and .cpp) or a glob (shaders/refine*).
  - in backticks, a code name: `A::b`, `func()`, `list[k]`, `kName`, `RTSDF_MACRO`, `Pass::kName`, `a.b`. Plain
    lower-case words (`bake`, `--band`), quoted strings, flags and command lines (`rtsdf bake ...`) are prose, not
    names; a bare file name (`refine_main.glsl`, `refine_closest[_cell].comp`) must be some file's name.
A name exists when the tree's code has it (C, C++ and GLSL comments do not count): `func()` as a call or
declaration `func(`, `list[k]` as `list[`, `A::b` with A and b in one file. A name cited right before a path in
parentheses or after a comma (`recordMask()` (lib/sdf/SdfPipeline.cpp)), or in the first sentence of a list item
whose first line starts with a path (shaders/refine_main.glsl reads `x[k]`), must be in that file's code (used or
declared there; a header stands for its .cpp too), or, for a shader, in a file that loads it by name.
"""
import fnmatch
import glob
import os
import re
import sys
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SEARCHED = ["lib", "apps", "python", "shaders", "tests", "scripts", "cmake", "bench", "fuzz", "examples"]
TOP_FOLDERS = SEARCHED + ["docs", "data"]
C_LIKE = (".h", ".hpp", ".c", ".cpp", ".glsl", ".comp", ".vert", ".frag", ".inl")
TEXT = C_LIKE + (".py", ".txt", ".cmake", ".in", ".sh", ".json", ".supp", ".toml", ".cfg")
SELF = os.path.relpath(os.path.abspath(__file__), ROOT)

# A span naming a file by itself (no folder), and a span that is a command line or a flag.
FILE_NAME = re.compile(r"^[\w\[\]*-]+(?:\.[\w\[\]*-]+)*\.(?:h|cpp|glsl|comp|py|json|obj|md|txt|cmake|sh|vdb)$")
COMMAND = re.compile(r"^(?:-|rtsdf |python3? |cmake |ctest |doxygen |xvfb-run |build/)")
C_COMMENT = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"', re.S)
IDENT = re.compile(r"[A-Za-z_]\w*")


def strip_c_comments(text):
    """C, C++ and GLSL comments removed; string literals kept (they hold names too: metadata keys, pass labels)."""
    return C_COMMENT.sub(lambda m: m.group(0) if m.group(0).startswith('"') else " ", text)


class Tree:
    """The searched folders' code: its words, the words called or declared as functions, the words indexed."""

    def __init__(self, root):
        self.root = root
        self.lib_folders = sorted(f for f in os.listdir(os.path.join(root, "lib"))
                                  if os.path.isdir(os.path.join(root, "lib", f))) if os.path.isdir(
                                      os.path.join(root, "lib")) else []
        self.files = {}  # relative path -> its code text
        for top in SEARCHED:
            for dirpath, dirs, names in os.walk(os.path.join(root, top)):
                dirs[:] = [d for d in dirs if not d.startswith(".") and d != "__pycache__"]
                for name in names:
                    path = os.path.join(dirpath, name)
                    rel = os.path.relpath(path, root)
                    if rel == SELF or not name.endswith(TEXT) and name != "CMakeLists.txt":
                        continue
                    with open(path, errors="ignore") as f:
                        text = f.read()
                    self.files[rel] = strip_c_comments(text) if name.endswith(C_LIKE) else text
        self.files_of = {}  # word -> files holding it
        self.called, self.indexed = set(), set()
        for rel, text in self.files.items():
            for w in set(IDENT.findall(text)):
                self.files_of.setdefault(w, set()).add(rel)
            self.called |= set(re.findall(r"\b([A-Za-z_]\w*)\s*(?:<[^<>;(){}]*>\s*)?\(", text))
            self.indexed |= set(re.findall(r"\b([A-Za-z_]\w*)\s*\[", text))

    def path_matches(self, cited):
        """The tree's files a cited path stands for (empty when it names nothing)."""
        cited = cited.rstrip("/")
        found = []
        for base in ("", "lib"):
            full = os.path.join(self.root, base, cited)
            rel = os.path.normpath(os.path.join(base, cited))
            if any(c in cited for c in "*?["):
                found += [os.path.relpath(p, self.root) for p in glob.glob(full)]
            elif os.path.isfile(full):
                found.append(rel)
            elif os.path.isdir(full):
                found += [f for f in self.files if f.startswith(rel + os.sep)] or [rel]
            else:  # a file without its extension: lib/sdf/SdfPipeline for its .h and .cpp
                found += [os.path.relpath(p, self.root) for p in glob.glob(glob.escape(full) + ".*")]
        return found

    def has_file_named(self, pattern):
        """Whether a file of the tree (the searched folders, docs/ and data/ too) or an embedded shader (a row of
        lib/Shaders.cmake: a variant is a name, not a file) is named @a pattern, where [optional] parts are
        wildcards."""
        if not hasattr(self, "names"):
            self.names = {n for top in TOP_FOLDERS for _, _, ns in os.walk(os.path.join(self.root, top)) for n in ns}
            table = os.path.join(self.root, "lib", "Shaders.cmake")
            if os.path.exists(table):
                with open(table) as f:
                    self.names |= set(re.findall(r'^\s*"([A-Za-z0-9_]+\.comp)\s', f.read(), re.M))
        glob_pattern = re.sub(r"\[[^\]]*\]", "*", pattern)
        return any(fnmatch.fnmatchcase(n, glob_pattern) for n in self.names)

    def runs_shader(self, name, scope):
        """Whether @a scope is a shader that a file holding @a name loads by its file name (a pass and its shader:
        `MaskCompactPass` (shaders/mask_compact.comp))."""
        if not scope.endswith((".comp", ".glsl")):
            return False
        quoted = '"' + os.path.basename(scope) + '"'
        return any(quoted in self.files[f] for f in self.files_of.get(name, ()))

    def stems(self, files):
        """@a files with their header/source siblings (a class is its .h and its .cpp)."""
        out = set()
        for f in files:
            stem = os.path.splitext(f)[0]
            out |= {g for g in self.files if os.path.splitext(g)[0] == stem} | {f}
        return out


def path_body(tree):
    """The regular expression of a cited path, one group: a top folder or a folder of lib/, then the rest."""
    tops = "|".join(sorted(set(TOP_FOLDERS) | set(tree.lib_folders), key=len, reverse=True))
    return r"((?:" + tops + r")/[\w./*-]*[\w*])"


def path_pattern(tree):
    return re.compile(r"(?<![\w./-])" + path_body(tree))


def code_names(span, paths):
    """The code names of one backticked span: (name, form) with form 'call', 'index' or 'word', and the
    qualified chains (A::b) in it."""
    text = re.sub(r'"[^"]*"', " ", span)
    for p in paths:
        text = text.replace(p, " ")
    names, chains = [], []
    for m in re.finditer(r"(?<![\w\-.])((?:[A-Za-z_]\w*(?:::|\.|->))*[A-Za-z_]\w*)(\s*\(|\[)?", text):
        parts = re.split(r"::|\.|->", m.group(1))  # (a word after '-' is a flag's: the look-behind skips it)
        after = (m.group(2) or "").strip()
        for i, part in enumerate(parts):
            last = i == len(parts) - 1
            form = ("call" if after == "(" else "index" if after == "[" else "word") if last else "word"
            codeish = (len(parts) > 1 or form != "word" or "_" in part.strip("_") or re.search(r"[A-Z]", part))
            if codeish and not part.isdigit():
                names.append((part, form))
        if "::" in m.group(1):
            chains.append(m.group(1).split("::"))
    return names, chains


def check_doc(tree, doc_text, doc_name):
    problems = []
    paths_re = path_pattern(tree)
    lines = doc_text.split("\n")
    in_fence = False
    for number, line in enumerate(lines, 1):
        if line.strip().startswith("```"):
            in_fence = not in_fence
            continue
        if in_fence:
            continue
        where = f"{doc_name}:{number}"
        line_paths = [m.group(1).rstrip(".") for m in paths_re.finditer(line)]
        for p in line_paths:
            if not tree.path_matches(p):
                problems.append(f"{where}: path {p} is not in the tree")
        # Names in backticks, each checked alone, then against the file it is cited beside.
        item = re.match(r"^\s*(?:\d+\.|-)\s+`?(\S+?)`?\s", line)  # a list item, its first word
        for m in re.finditer(r"`([^`]+)`", line):
            span = m.group(1)
            span_paths = [q.group(1).rstrip(".") for q in paths_re.finditer(span)]
            if FILE_NAME.match(span):  # refine_main.glsl, refine_closest[_cell].comp: a file somewhere in the tree
                if not tree.has_file_named(span):
                    problems.append(f"{where}: `{span}`: no file of the tree is named so")
                continue
            if COMMAND.match(span):  # a command line or a flag: its words are prose
                continue
            names, chains = code_names(span, span_paths)
            for name, form in names:
                if name not in tree.files_of:
                    problems.append(f"{where}: `{span}`: {name} is not in the tree's code")
                elif form == "call" and name not in tree.called:
                    problems.append(f"{where}: `{span}`: {name}() is neither called nor declared in the tree")
                elif form == "index" and name not in tree.indexed:
                    problems.append(f"{where}: `{span}`: {name}[] is never indexed in the tree")
            for chain in chains:
                holders = [tree.files_of.get(c, set()) for c in chain[-2:]]
                if all(holders) and not set.intersection(*holders):
                    problems.append(f"{where}: `{span}`: no file has both {' and '.join(chain[-2:])}")
            # Scope: the path right after the span, "(path" or ", path"; or the item's leading path.
            rest = line[m.end():]
            scoped = re.match(r"\s*(?:\(|,)\s*" + path_body(tree), rest)
            scope = scoped.group(1).rstrip(".") if scoped else None
            if scope is None and item and paths_re.fullmatch(item.group(1).rstrip(".:,")):
                first_sentence_end = re.search(r"[.:;]\s", line[item.end():])
                if first_sentence_end is None or m.start() < item.end() + first_sentence_end.start():
                    scope = item.group(1).rstrip(".:,") if not span_paths else None
            if scope is None or scope in span_paths:
                continue
            files = tree.stems(tree.path_matches(scope))
            for name, _ in names:
                if files and name in tree.files_of and not (tree.files_of[name] & files) and \
                        not tree.runs_shader(name, scope):
                    problems.append(f"{where}: `{span}`: {name} is not in {scope}")
    return problems


def main(docs):
    tree = Tree(ROOT)
    problems = []
    for doc in docs:
        with open(os.path.join(ROOT, doc)) as f:
            problems += check_doc(tree, f.read(), doc)
    for p in problems:
        print(p)
    print(f"{', '.join(docs)}: {'every cited name and path exists' if not problems else f'{len(problems)} stale'}")
    return 1 if problems else 0


SELF_TEST_TREE = {
    "lib/sdf/Pass.h": "struct Params { unsigned band; };\nconstexpr int kBindingList = 1;\n"
                      "void recordPass(int x); // oldName() in a comment does not count\n",
    "lib/sdf/Pass.cpp": '#include "sdf/Pass.h"\nvoid recordPass(int x) { (void)x; }\n',
    "lib/sdf/MainPass.h": 'struct Pass { const char* shader = "main.glsl"; };\n',
    "shaders/main.glsl": "layout(binding = kBindingList) buffer L { uint list[]; };\nvoid main() { list[0] = 1u; }\n",
}
SELF_TEST_GOOD = """# Notes
1. `recordPass()` (lib/sdf/Pass.cpp) binds the list at `kBindingList` (lib/sdf/Pass.h): `Params::band`.
2. shaders/main.glsl reads `list[k]`; see gpu/ and lib/sdf/Pass, shaders/*.glsl. `rtsdf bake --band 0.1`,
   `--device NAME|INDEX`, `main[_cpu].glsl`; `Pass` (shaders/main.glsl) loads it.
```
oldName() inside a fence is an example
```
"""
# Each stale citation: a line added to the good document, and a piece of the message it must bring.
SELF_TEST_STALE = [
    ("Calls `oldName()`.", "oldName is not in the tree"),
    ("Binds `kBindingMask`.", "kBindingMask is not in the tree"),
    ("Reads `band()`.", "band() is neither called nor declared"),
    ("3. shaders/main.glsl reads `mask[k]`.", "mask is not in the tree"),
    ("3. shaders/main.glsl reads `recordPass()` too.", "recordPass is not in shaders/main.glsl"),
    ("`kBindingList` (shaders/gone.glsl)", "path shaders/gone.glsl is not in the tree"),
    ("See lib/sdf/Gone.h.", "path lib/sdf/Gone.h is not in the tree"),
    ("`Params::list`.", "no file has both Params and list"),
    ("`Params` (shaders/main.glsl)", "Params is not in shaders/main.glsl"),
    ("The shader `gone[_cpu].comp`.", "`gone[_cpu].comp`: no file of the tree is named so"),
]


def self_test():
    failures = []
    with tempfile.TemporaryDirectory() as base:
        for rel, text in SELF_TEST_TREE.items():
            os.makedirs(os.path.dirname(os.path.join(base, rel)), exist_ok=True)
            with open(os.path.join(base, rel), "w") as f:
                f.write(text)
        tree = Tree(base)
        good = check_doc(tree, SELF_TEST_GOOD, "good.md")
        if good:
            failures.append(f"the current citations fail: {good}")
        for line, expected in SELF_TEST_STALE:
            found = check_doc(tree, SELF_TEST_GOOD + line + "\n", "stale.md")
            if len(found) != 1 or expected not in found[0]:
                failures.append(f"'{line}': expected one problem with '{expected}', got {found}")
    for f in failures:
        print(f)
    print(f"{len(SELF_TEST_STALE)} stale citations and a current document: "
          f"{'each reported' if not failures else 'FAILED'}")
    return 1 if failures else 0


if __name__ == "__main__":
    if sys.argv[1:] == ["--self-test"]:
        sys.exit(self_test())
    if any(a.startswith("-") for a in sys.argv[1:]):
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1:] or ["docs/design.md"]))
