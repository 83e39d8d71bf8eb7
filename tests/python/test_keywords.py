"""The keywords the command line has: up= as `bake --up`, grid= as `compare --grid` (rtsdf.read, rtsdf.compare).

Run by ctest with PYTHONPATH at the built module and RTSDF_BINARY at the command line.
"""
import os
import subprocess

import numpy as np
import pytest

import rtsdf

DATA = os.environ.get("RTSDF_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "data"))
RTSDF = os.environ.get("RTSDF_BINARY", "rtsdf")
BUNNY = os.path.join(DATA, "scenes", "bunny.json")


def test_bake_up_z_equals_the_command_lines_bake_up_z(tmp_path):
    pyopenvdb = pytest.importorskip("pyopenvdb")
    ours, cli = tmp_path / "py.vdb", tmp_path / "cli.vdb"
    field = rtsdf.bake(BUNNY, method="exact", res=40, band="3vox", up="z")
    field.write(ours)
    subprocess.run([RTSDF, "-q", "bake", BUNNY, "--method", "exact", "--res", "40", "--band", "3vox", "--up", "z",
                    "-o", str(cli)], check=True)
    # The same values and active voxels, voxel for voxel ...
    assert rtsdf.count_different_values(ours, cli) == 0
    # ... under the same turned transform.
    a, b = pyopenvdb.read(str(ours), "surface"), pyopenvdb.read(str(cli), "surface")
    assert a.metadata["rtsdf:up"] == b.metadata["rtsdf:up"] == "z"
    for ijk in [(0, 0, 0), (1, 2, 3), (17, -5, 40)]:
        assert a.transform.indexToWorld(ijk) == pytest.approx(b.transform.indexToWorld(ijk), abs=0.0)
    # Z up: the scene's y (up) axis is the file's z axis.
    y_up = rtsdf.bake(BUNNY, method="exact", res=40, band="3vox")
    y_up.write(tmp_path / "y.vdb")
    c = pyopenvdb.read(str(tmp_path / "y.vdb"), "surface")
    assert c.metadata.get("rtsdf:up", "y") == "y"
    assert a.transform.indexToWorld((0, 1, 0))[2] == pytest.approx(c.transform.indexToWorld((0, 1, 0))[1])
    # The arrays stay in the scene's frame: both bakes hold the same values.
    np.testing.assert_array_equal(field.values, y_up.values)


def test_up_is_checked_and_write_can_turn_a_y_up_bake(tmp_path):
    with pytest.raises(rtsdf.SettingError, match="up axis 'x'"):
        rtsdf.bake(BUNNY, res=16, up="x")
    field = rtsdf.bake(BUNNY, method="exact", res=24, band="3vox")
    field.write(tmp_path / "z.vdb", up="z")
    back = rtsdf.read(tmp_path / "z.vdb")  # turned back into the scene's frame
    np.testing.assert_array_equal(back.values, field.values)
    assert back.origin == pytest.approx(field.origin) and back.voxel_size == pytest.approx(field.voxel_size)
    with pytest.raises(rtsdf.SettingError, match="up axis"):
        field.write(tmp_path / "w.vdb", up="w")


@pytest.fixture(scope="module")
def two_grids(tmp_path_factory):
    """A .vdb holding two level sets, 'coarse' (res 24) and 'fine' (res 40), both rtsdf's."""
    pyopenvdb = pytest.importorskip("pyopenvdb")
    folder = tmp_path_factory.mktemp("grids")
    grids = []
    for name, res in (("coarse", 24), ("fine", 40)):
        rtsdf.bake(BUNNY, method="exact", res=res, band="3vox").write(folder / f"{name}.vdb")
        grid = pyopenvdb.read(str(folder / f"{name}.vdb"), "surface")
        grid.name = name
        grids.append(grid)
    path = folder / "both.vdb"
    pyopenvdb.write(str(path), grids=grids)
    return path


def test_read_picks_the_named_grid(two_grids):
    fine, coarse = rtsdf.read(two_grids, grid="fine"), rtsdf.read(two_grids, grid="coarse")
    assert fine.voxel_size < coarse.voxel_size
    assert fine.values.shape == rtsdf.bake(BUNNY, method="exact", res=40, band="3vox").values.shape


def test_a_wrong_grid_name_raises_with_the_grid_list(two_grids):
    with pytest.raises(rtsdf.Error, match=r"no grid named 'medium' \(grids: .*coarse.*fine"):
        rtsdf.read(two_grids, grid="medium")
    with pytest.raises(rtsdf.Error, match=r"no grid named 'medium' \(grids: .*coarse.*fine"):
        rtsdf.compare(two_grids, two_grids, grid="medium")
    with pytest.raises(rtsdf.SettingError, match="2 candidate level sets"):  # which one is meant?
        rtsdf.read(two_grids)


def test_compare_reads_the_named_grid_and_against_an_anchor(two_grids, tmp_path):
    same = rtsdf.compare(two_grids, two_grids, grid="fine")
    assert same["max_abs"] == 0.0 and same["voxels"] > 0 and same["sign_disagreement"] == 0.0
    rtsdf.read(two_grids, grid="fine").write(tmp_path / "fine.vdb")
    exact = rtsdf.compare(tmp_path / "fine.vdb", against="exact")  # the anchor is the exact bake itself
    assert exact["max_abs"] == pytest.approx(0.0, abs=1e-6) and "exact bake of" in exact["b"]
    assert "mean" in exact["report"]


@pytest.mark.parametrize("keywords, named, cli", [
    (dict(method="exact", coarse=32), "coarse=", ["-m", "exact", "--coarse", "32"]),
    (dict(method="exact", rays=3), "rays=", ["-m", "exact", "--rays", "3"]),
    (dict(method="rtsdf", res=32, refine="rays", rays=2, closest_search="cell"), "closest_search=",
     ["-m", "rtsdf", "--res", "32", "--refine", "rays", "--rays", "2", "--closest-search", "cell"]),
    (dict(method="rtsdf", res=32, refine="closest", rays=0, alpha=0.5), "alpha=",
     ["-m", "rtsdf", "--res", "32", "--refine", "closest", "--rays", "0", "--alpha", "0.5"]),
])
def test_bake_refuses_a_keyword_it_would_ignore_as_the_command_line_refuses_its_flag(tmp_path, keywords, named, cli):
    with pytest.raises(ValueError) as python_error:
        rtsdf.bake(BUNNY, **keywords)
    message = str(python_error.value)
    assert message.startswith(named), message
    out = tmp_path / "x.vdb"
    run = subprocess.run([RTSDF, "bake", BUNNY, "-o", str(out)] + cli, capture_output=True, text=True)
    assert run.returncode != 0 and not out.exists()
    flag = "--" + named[:-1].replace("_", "-")
    # the same reason after the keyword as after the flag
    assert message[len(named):] in run.stderr.replace(flag, ""), (message, run.stderr)


def test_bake_takes_the_keywords_its_method_reads():
    field = rtsdf.bake(BUNNY, method="rtsdf", res=32, refine="closest", rays=0, frames=1, closest_search="voxel")
    assert field.method == "rtsdf"


def test_a_pipeline_refuses_a_keyword_it_would_ignore():
    with pytest.raises(ValueError, match="^closest_search= "):
        rtsdf.Pipeline(BUNNY, refine="rays", rays=2, closest_search="cell")
    assert rtsdf.Pipeline(BUNNY, coarse=16, fine=32, refine="closest", closest_search="cell") is not None
