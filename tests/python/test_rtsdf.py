"""The Python module against analytic distances, the command line's bakes, and bad input (ctest label python).

Run by ctest with PYTHONPATH at the built module and RTSDF_BINARY at the command line.
"""
import json
import os
import subprocess

import numpy as np
import pytest

import rtsdf
from meshgen import icosphere

DATA = os.environ.get("RTSDF_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "data"))
RTSDF = os.environ.get("RTSDF_BINARY", "rtsdf")


@pytest.fixture(scope="module")
def sphere_obj(tmp_path_factory):
    verts, faces = icosphere(4)
    path = tmp_path_factory.mktemp("sphere") / "sphere.obj"
    with open(path, "w") as f:
        f.writelines(f"v {x:.9f} {y:.9f} {z:.9f}\n" for x, y, z in verts)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
    return str(path)


def test_sphere_distances_equal_the_analytic_ones(sphere_obj):
    rng = np.random.default_rng(3)
    points = rng.uniform(-2.0, 2.0, size=(4000, 3))
    d = rtsdf.distance(sphere_obj, points)
    # dtype in = dtype out: float64 points (numpy's default) give float64 distances, float32 ones float32.
    assert d.shape == (4000,) and d.dtype == np.float64
    assert rtsdf.distance(sphere_obj, points[:10].astype(np.float32)).dtype == np.float32
    analytic = np.linalg.norm(points, axis=1) - 1.0
    # The mesh lies inside the sphere by at most its sagitta (edges of ~0.076 at 4 levels: 7.3e-4).
    assert np.max(np.abs(d - analytic)) < 2e-3
    assert np.all(np.sign(d[np.abs(analytic) > 2e-3]) == np.sign(analytic[np.abs(analytic) > 2e-3]))
    scene = rtsdf.load_scene(sphere_obj)
    assert scene.triangles == 20 * 4 ** 4
    assert np.array_equal(rtsdf.distance(scene, points[:10]), d[:10])


def test_bake_equals_the_command_line(tmp_path):
    scene = os.path.join(DATA, "scenes", "bunny.json")
    field = rtsdf.bake(scene, method="exact", res=40, band=0.1)
    nx, ny, nz = field.values.shape
    assert max(nx, ny, nz) >= 40 and field.values.dtype == np.float32
    assert field.active.dtype == bool and field.active.shape == field.values.shape
    assert 1000 < field.active.sum() < field.active.size
    # Inside the band the values are the distances; outside it, +-band.
    assert np.all(np.abs(field.values[field.active]) <= field.band + 1e-6)
    assert np.all(np.abs(field.values[~field.active]) == pytest.approx(field.band))
    # index [i, j, k] = x, y, z: voxel (i, j, k)'s centre is origin + (i + 0.5, j + 0.5, k + 0.5) * voxel_size.
    i, j, k = np.unravel_index(np.argmin(np.where(field.active, field.values, np.inf)), field.values.shape)
    centre = np.array(field.origin) + (np.array([i, j, k]) + 0.5) * field.voxel_size
    assert rtsdf.distance(scene, centre[None, :])[0] == pytest.approx(field.values[i, j, k], abs=1e-5)
    ours = tmp_path / "python.vdb"
    field.write(str(ours))
    cli = tmp_path / "cli.vdb"
    subprocess.run([RTSDF, "-q", "bake", scene, "--method", "exact", "--res", "40", "--band", "0.1", "-o", str(cli)],
                   check=True)
    out = subprocess.run([RTSDF, "compare", str(ours), str(cli)], check=True, capture_output=True, text=True).stdout
    assert "(0 only in A, 0 only in B)" in out and "max 0.0000 voxels" in out, out


def test_rtsdf_bake_and_pipeline_frames():
    scene = rtsdf.load_scene(os.path.join(DATA, "scenes", "default.json"))
    # Grids over the scene at time 0 (one frame of bounds), as a bake at time 0 has them.
    pipe = rtsdf.Pipeline(scene, frames=1, coarse=32, fine=64, refine="closest", rays=0)
    first = pipe.frame(0.0)
    second = pipe.frame(0.0)
    assert first["mask_voxels"] > 1000 and first["refined_voxels"] == first["mask_voxels"]
    assert first["cut_voxels"] == 0  # no walk here runs out of a CPU device's loop budget (none on a GPU)
    # The open teapot's winding number lies near 1/2 beside its handle's ends: those voxels take the exact sum's side.
    teapot = rtsdf.Pipeline(rtsdf.load_scene(os.path.join(DATA, "scenes", "teapot.json")), frames=1, coarse=64,
                            fine=128, refine="closest", rays=0).frame(0.0)
    assert 0 < teapot["near_half_voxels"] < teapot["refined_voxels"] and teapot["near_half_kept"] == 0
    assert second["refined_voxels"] == 0  # nothing moved, everything settled
    # The orbiting teapot, once the band settled (a frame without sign rays, four with them): of the voxels listed for
    # it alone, those it came near none of keep their values unwalked; none before.
    for rays, settle in ((0, 1), (1, 4)):
        moving = rtsdf.Pipeline(scene, frames=settle + 1, coarse=32, fine=64, refine="closest", rays=rays)
        steps = [moving.frame(f / 30) for f in range(settle + 1)]
        assert all(step["moved_kept_voxels"] == 0 for step in steps[:settle])
        assert 0 < steps[settle]["moved_kept_voxels"] < steps[settle]["refined_voxels"]
    assert "VoxelizePass" in first["pass_ms"]
    assert "VoxelizePass" not in second["pass_ms"]  # nothing moved: the coarse SDF is kept, not rebuilt
    fine = pipe.fine()
    baked = rtsdf.bake(scene, method="rtsdf", res=64, coarse=32, refine="closest", rays=0, frames=1)
    assert fine.values.shape == baked.values.shape
    assert np.max(np.abs(fine.values[baked.active] - baked.values[baked.active])) < 1e-5
    # Only the bricks under the band on the GPU: the same field, resolved on the host.
    sparse = rtsdf.Pipeline(scene, frames=1, coarse=32, fine=64, refine="closest", rays=0, fine_storage="sparse")
    sparse.frame(0.0)
    assert np.array_equal(sparse.fine().values, fine.values)


def test_a_cascade_bake_returns_every_level(tmp_path):
    scene = os.path.join(DATA, "scenes", "default.json")
    # The default band (6 voxels) is each level's own: level i's is 2^i times level 0's in scene units.
    levels = rtsdf.bake(scene, method="rtsdf", res=32, refine="closest", rays=0, frames=1, cascades=2)
    assert isinstance(levels, list) and len(levels) == 2
    assert levels[1].voxel_size == pytest.approx(2 * levels[0].voxel_size)
    assert levels[0].band == pytest.approx(6 * levels[0].voxel_size)
    assert levels[1].band == pytest.approx(6 * levels[1].voxel_size)
    for level in levels:
        assert level.active.sum() > 500
        assert np.all(np.abs(level.values[level.active]) <= level.band * (1 + 1e-5))
    # The same levels as the command line's, level for level.
    cli = tmp_path / "levels.vdb"
    subprocess.run([RTSDF, "-q", "bake", scene, "-m", "rtsdf", "--res", "32", "--refine", "closest", "--rays", "0",
                    "--frames", "1", "--cascades", "2", "-o", str(cli)], check=True)
    for i, level in enumerate(levels):
        theirs = rtsdf.read(str(cli), grid=f"surface_L{i}")
        assert theirs.shape == level.shape and theirs.voxel_size == level.voxel_size
        assert np.max(np.abs(theirs.values[level.active] - level.values[level.active])) < 1e-5


def test_cascades_follow_a_camera_by_scrolling():
    scene = rtsdf.load_scene(os.path.join(DATA, "scenes", "default.json"))
    kw = dict(cascades=2, cascade_extent=0.6, coarse=16, fine=32, refine="closest", rays=0, band=0.05)
    camera = [-0.3, 0.45, 0.1]
    levels = rtsdf.Cascades(scene, camera=camera, **kw)
    assert levels.levels == 2 and "2 levels of coarse 16 / fine 32" in repr(levels)
    first = levels.frame(0.0)
    assert len(first) == 2 and all(level["refined_voxels"] > 0 for level in first)
    assert all(level["pool_bricks"] >= level["active_bricks"] > 0 for level in first)
    # What the levels hold as allocated, against the estimates with the pools (no more than 10% apart here).
    estimated = sum(level["device_bytes"] for level in first)
    assert 0.9 * estimated < levels.device_bytes < 1.1 * estimated
    # The orbiting teapot is far from level 0 (0.6 wide): its coarse passes are skipped, level 1 sees it move.
    moving = levels.frame(0.1)
    assert moving[0]["moved_instances"] == 0 and "ExactEdtPass" in moving[0]["skipped_passes"]
    assert moving[1]["moved_instances"] == 1 and moving[1]["skipped_passes"] == []
    # The teapot is outside both grids here: its motion leaves their coarse SDFs, so nothing is upsampled again.
    assert first[1]["upsampled_voxels"] == 32 ** 3 and moving[1]["upsampled_voxels"] == 0
    # Level 0's move is 4 coarse voxels of 0.0375 (a brick of 8 fine voxels): 0.1 along -x moves it once, over
    # surfaces that enter it.
    camera[0] -= 0.1
    move = levels.move_to(camera)
    assert move["moved"] == [0] and move["rebuilt"] == []
    after = levels.frame(0.1)
    fresh = rtsdf.Cascades(scene, camera=camera, time=0.1, **kw)
    refreshed = fresh.frame(0.1)
    assert 0 < after[0]["refined_voxels"] < refreshed[0]["refined_voxels"]  # only what entered level 0
    for i in range(2):
        ours, theirs = levels.level(i), fresh.level(i)
        assert ours.shape == theirs.shape
        assert np.array_equal(ours.active, theirs.active)
        assert np.max(np.abs(ours.values[ours.active] - theirs.values[ours.active])) < 1e-3 * ours.voxel_size
    with pytest.raises(IndexError):
        levels.level(2)
    with pytest.raises(rtsdf.SettingError, match="cascades"):
        rtsdf.Cascades(scene, cascades=1)


def test_a_moving_instance_upsamples_only_near_what_it_changed():
    scene = rtsdf.load_scene(os.path.join(DATA, "scenes", "default.json"))
    kw = dict(cascades=2, cascade_extent=0.6, coarse=16, fine=32, refine="closest", rays=0, band=0.05)
    levels = rtsdf.Cascades(scene, camera=[0.4, 0.3, 0.25], **kw)  # around the teapot's orbit
    first = levels.frame(0.0)
    assert [level["upsampled_voxels"] for level in first] == [32 ** 3, 32 ** 3]
    moving = levels.frame(0.1)
    # Level 1 (1.2 wide) rewrites the fine voxels near the coarse voxels the teapot changed, not its whole grid.
    assert moving[1]["moved_instances"] == 1 and 0 < moving[1]["upsampled_voxels"] < 32 ** 3 / 2
    # The first frame builds the coarse SDF and visits the mask over every voxel; moving, level 1's mask visits what
    # the teapot can reach (its coarse region is the whole of these 4^3 blocks of 4^3 voxels).
    assert [level["coarse_rebuilt_voxels"] for level in first] == [16 ** 3, 16 ** 3]
    assert [level["mask_visited_voxels"] for level in first] == [16 ** 3, 16 ** 3]
    assert 0 < moving[1]["mask_visited_voxels"] < 16 ** 3 and moving[1]["coarse_rebuilt_voxels"] > 0


def test_a_moving_instance_rebuilds_the_coarse_sdf_and_visits_the_mask_only_where_it_reaches():
    scene = rtsdf.load_scene(os.path.join(DATA, "scenes", "default.json"))
    pipe = rtsdf.Pipeline(scene, frames=3, fps=30.0, coarse=48, fine=96, refine="closest", rays=0)
    first = pipe.frame(0.0)
    grid = first["coarse_rebuilt_voxels"]
    assert grid > 0 and first["mask_visited_voxels"] == grid and first["coarse_voxelized_voxels"] == grid
    for t in (1 / 30, 2 / 30):
        moving = pipe.frame(t)
        # Measured: 39% of the grid rebuilt, 14-18% visited by the mask, 0.9% voxelized (the teapot's swept box).
        assert moving["moved_instances"] == 1
        assert 0 < moving["coarse_rebuilt_voxels"] < grid / 2 and 0 < moving["mask_visited_voxels"] < grid / 4
        assert 0 < moving["coarse_voxelized_voxels"] < moving["coarse_rebuilt_voxels"]


def test_cascades_above_level_0_refine_near_the_view_given():
    scene = rtsdf.load_scene(os.path.join(DATA, "scenes", "default.json"))
    kw = dict(cascades=2, cascade_extent=0.6, coarse=16, fine=32, refine="closest", rays=0, band=0.05)
    camera = [-0.3, 0.45, 0.1]
    limited = rtsdf.Cascades(scene, camera=camera, cascade_view_margin=1, **kw)
    limited.move_to(camera, target=[0.4, 0.2, -0.3], fov=0.5, aspect=16 / 9)
    whole = rtsdf.Cascades(scene, camera=camera, **kw)  # no view given: every level refines its whole band
    ours, theirs = limited.frame(0.0), whole.frame(0.0)
    assert ours[0]["refined_voxels"] == theirs[0]["refined_voxels"]
    assert 0 < ours[1]["refined_voxels"] < theirs[1]["refined_voxels"]
    # Level 1's field holds the voxels in view only, each the value the whole level has there.
    mine, full = limited.level(1), whole.level(1)
    assert 0 < mine.active.sum() < full.active.sum()
    assert np.all(full.active[mine.active])
    assert np.array_equal(mine.values[mine.active], full.values[mine.active])
    with pytest.raises(rtsdf.Error, match="looks at its own position"):
        limited.move_to(camera, target=camera)


def test_log_is_quiet_unless_asked(capfd):
    bunny = os.path.join(DATA, "scenes", "bunny.json")
    rtsdf.bake(bunny, res=16)
    assert "[info]" not in capfd.readouterr().err
    rtsdf.set_verbosity(0)
    rtsdf.bake(bunny, res=16)
    rtsdf.set_verbosity(-1)
    assert "[info]" in capfd.readouterr().err


def test_to_pyopenvdb():
    pyopenvdb = pytest.importorskip("pyopenvdb")
    field = rtsdf.bake(os.path.join(DATA, "scenes", "bunny.json"), res=24)
    grid = field.to_pyopenvdb()
    assert isinstance(grid, pyopenvdb.FloatGrid)
    assert grid.activeVoxelCount() == int(field.active.sum())


def test_bad_input_raises_the_documented_errors(tmp_path):
    with pytest.raises(rtsdf.Error, match="missing.json"):
        rtsdf.load_scene(str(tmp_path / "missing.json"))
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"rtsdf_scene": 1, "meshes": {}, "instances": [{"name": "a", "mesh": "nope"}]}))
    with pytest.raises(rtsdf.Error, match="bad.json"):
        rtsdf.bake(str(bad))
    bunny = os.path.join(DATA, "scenes", "bunny.json")
    with pytest.raises(rtsdf.SettingError, match="band"):
        rtsdf.bake(bunny, band=-1.0)
    with pytest.raises(rtsdf.SettingError, match="bake method"):
        rtsdf.bake(bunny, method="magic")
    with pytest.raises(TypeError, match="colour"):
        rtsdf.bake(bunny, colour=3)
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        rtsdf.distance(bunny, np.zeros((4, 2)))
    with pytest.raises(ValueError, match="not finite"):
        rtsdf.distance(bunny, np.array([[0.0, np.nan, 0.0]]))
    assert issubclass(rtsdf.SettingError, rtsdf.Error) and issubclass(rtsdf.Error, RuntimeError)


def test_any_look_ahead_keeps_the_levels_nested():
    # move_to clamps each component of look_ahead (CascadeShape::maxLookAhead) so that level 0 stays a fine voxel of
    # level 1 inside it, where the march blends into level 1; unclamped, 5 units would put level 0 (0.6 wide) far
    # outside level 1 (1.2 wide, on the camera).
    scene = rtsdf.load_scene(os.path.join(DATA, "scenes", "default.json"))
    kw = dict(cascades=2, cascade_extent=0.6, coarse=16, fine=64, refine="closest", rays=0, band=0.05)
    camera = [-0.3, 0.45, 0.1]
    levels = rtsdf.Cascades(scene, camera=camera, **kw)
    for ahead in ([5.0, 0.0, 0.0], [-5.0, 0.0, 0.0], [0.0, 0.0, 5.0], [3.0, -3.0, 3.0]):
        levels.move_to(camera, look_ahead=ahead)
        levels.frame(0.0)
        lo, hi, spare = [], [], levels.level(1).voxel_size
        for i in range(2):
            level = levels.level(i)
            lo.append(np.array(level.origin))
            hi.append(lo[-1] + np.array(level.shape) * level.voxel_size)
        assert np.all(lo[0] >= lo[1] + spare - 1e-9) and np.all(hi[0] <= hi[1] - spare + 1e-9), ahead
        centre = 0.5 * (lo[0] + hi[0])
        # Level 0 reaches ahead along every axis asked for (by whole moves of 2 coarse voxels, 0.075).
        for axis in range(3):
            if ahead[axis] != 0.0:
                assert (centre[axis] - camera[axis]) * ahead[axis] > 0.07, (ahead, centre)
