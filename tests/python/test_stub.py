"""The typed stub (python/rtsdf/*.pyi) describes the module as built, every public object has a docstring and a
readable repr (ctest label python)."""
import ast
import inspect
import os
import types

import numpy as np
import pytest

import rtsdf

STUBS = os.path.join(os.path.dirname(__file__), "..", "..", "python", "rtsdf")
DATA = os.environ.get("RTSDF_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "data"))
# The native extension: rtsdf itself, or rtsdf._rtsdf inside the package.
NATIVE = getattr(rtsdf, "_rtsdf", rtsdf)


def public(names):
    return {n for n in names if not n.startswith("_")}


def stub_names(filename):
    """Top-level public names of a stub and, per class, its public members; star imports of a sibling stub
    followed."""
    tree = ast.parse(open(os.path.join(STUBS, filename)).read())
    names, classes = set(), {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            names.add(node.name)
            classes[node.name] = public(n.name for n in node.body if isinstance(n, ast.FunctionDef))
        elif isinstance(node, ast.FunctionDef):
            names.add(node.name)
        elif isinstance(node, ast.Assign):
            names.update(t.id for t in node.targets if isinstance(t, ast.Name))
        elif isinstance(node, ast.ImportFrom) and node.level == 1:
            if [a.name for a in node.names] == ["*"]:
                sub, sub_classes = stub_names(node.module + ".pyi")
                names |= sub
                classes.update(sub_classes)
            else:
                names.update(a.asname or a.name for a in node.names if a.asname == a.name or node.module is None)
    return public(names), classes


def test_the_native_stub_names_what_the_module_has():
    names, classes = stub_names("_rtsdf.pyi")
    assert names == public(dir(NATIVE))
    for name, members in classes.items():
        assert members == public(dir(getattr(NATIVE, name))) - public(dir(Exception)), name


def test_the_package_stub_names_what_import_rtsdf_gives():
    names, _ = stub_names("__init__.pyi")
    assert names == {n for n in public(dir(rtsdf)) if not isinstance(getattr(rtsdf, n), types.ModuleType)}
    assert os.path.exists(os.path.join(STUBS, "py.typed"))


def documented(obj):
    """pybind11 puts the signature on the first line of a function's __doc__: the text must follow it."""
    doc = inspect.getdoc(obj) or ""
    lines = [line for line in doc.splitlines() if line.strip()]
    if callable(obj) and not isinstance(obj, type):
        lines = [line for line in lines if not line.lstrip().startswith(getattr(obj, "__name__", "?") + "(")
                 and not line.strip().startswith("Overloaded function")]
    return bool(lines)


def test_every_public_object_has_a_docstring():
    missing = []
    for name in public(dir(NATIVE)):
        obj = getattr(NATIVE, name)
        if not documented(obj):
            missing.append(name)
        if isinstance(obj, type) and not issubclass(obj, Exception):
            for member in public(dir(obj)):
                attr = inspect.getattr_static(obj, member)
                if not documented(attr):
                    missing.append(f"{name}.{member}")
    assert not missing


def test_every_object_has_a_readable_repr(tmp_path):
    bunny = os.path.join(DATA, "scenes", "bunny.json")
    scene = rtsdf.load_scene(bunny)
    assert repr(scene).startswith("rtsdf.Scene('") and "1 instance" in repr(scene) and "triangles" in repr(scene)
    field = rtsdf.bake(scene, res=16)
    r = repr(field)
    assert r.startswith("rtsdf.Field(exact: ") and "voxels of" in r and f"{field.active.sum()} active" in r
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
    mesh = rtsdf.Mesh(v, [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], name="tet")
    assert repr(mesh) == "rtsdf.Mesh('tet', 4 vertices, 4 triangles, watertight)"
    pipe = rtsdf.Pipeline(mesh, frames=1, coarse=8, fine=16, refine="closest", rays=0)
    assert repr(pipe).startswith("rtsdf.Pipeline(<mesh 'tet'>, coarse ") and "0 frames run" in repr(pipe)
