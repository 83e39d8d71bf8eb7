"""rtsdf.batch on a local Dask cluster of 2 workers (loopback only): every item accounted for, bad meshes failed with
their reason, a killed worker and Ctrl-C losing nothing, a rerun baking nothing, a tiled bake equal to the whole one.

Run by ctest (Python.Batch) with PYTHONPATH at the built package and RTSDF_DATA_DIR at data/.
"""
import hashlib
import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import rtsdf
import rtsdf.batch as batch
from meshgen import icosphere

distributed = pytest.importorskip("distributed")
pyopenvdb = pytest.importorskip("pyopenvdb")

DATA = os.environ.get("RTSDF_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "data"))
GOOD, RES, BAND = 35, 24, "3vox"


def write_obj(path, verts, faces):
    with open(path, "w") as f:
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in verts)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)


def generate(folder, good=GOOD):
    """good spheres (radius and centre in their name's row of spheres.json) and 5 bad meshes: {name: reason}."""
    folder.mkdir(parents=True, exist_ok=True)
    verts, faces = icosphere(3)
    spheres = {}
    for i in range(good):
        radius, centre = 0.5 + 0.05 * i, np.array([0.1 * i, -0.2 * i, 0.03 * i])
        write_obj(folder / f"sphere{i:02d}.obj", verts * radius + centre, faces)
        spheres[f"sphere{i:02d}"] = (radius, centre)
    (folder / "bad_empty.obj").write_text("")
    (folder / "bad_garbage.ply").write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 99\n\x00\xff")
    write_obj(folder / "bad_index.obj", verts[:3], [(0, 1, 40)])
    write_obj(folder / "bad_nan.obj", np.array([[0, 0, 0], [1, 0, 0], [float("nan"), 1, 0]]), [(0, 1, 2)])
    (folder / "bad_truncated.stl").write_bytes(b"\0" * 80 + (1000).to_bytes(4, "little") + b"\0" * 50)
    return spheres


def rows_of(out):
    with open(os.path.join(out, "manifest.jsonl")) as f:
        return [json.loads(line) for line in f]


def check_consistent(out):
    """Every row parses, the outputs of each item's last done row exist whole (hash) and read, no temporary file."""
    rows = rows_of(out)
    for row in {r["name"]: r for r in rows}.values():  # a later row supersedes an item's earlier ones
        if row["status"] in ("done", "cached"):
            for kind, name in row["outputs"].items():
                with open(os.path.join(out, name), "rb") as f:
                    assert hashlib.sha256(f.read()).hexdigest() == row["sha256"][kind], name
            grid = pyopenvdb.read(os.path.join(out, row["outputs"]["vdb"]), "surface")
            assert grid.activeVoxelCount() == row["active_voxels"] > 0
    assert not [f for f in os.listdir(out) if f.endswith(".tmp") or f.startswith(".")]
    return rows


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as c:
        with distributed.Client(c) as cl:
            yield cl


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("meshes")
    return folder, generate(folder)


@pytest.fixture(scope="module")
def first_run(client, meshes, tmp_path_factory):
    out = str(tmp_path_factory.mktemp("out"))
    summary = batch.run([str(meshes[0])], out, client=client, res=RES, band=BAND, samples=200)
    return out, summary


def test_every_item_is_accounted_for_and_bad_meshes_fail_with_their_reason(first_run, meshes):
    out, summary = first_run
    assert (summary["done"], summary["cached"], summary["failed"]) == (GOOD, 0, 5)
    rows = check_consistent(out)
    assert sorted(r["name"] for r in rows) == sorted([f"sphere{i:02d}" for i in range(GOOD)] +
                                                     ["bad_empty", "bad_garbage", "bad_index", "bad_nan",
                                                      "bad_truncated"])
    for row in rows:
        if row["name"].startswith("bad_"):
            assert row["status"] == "failed" and row["outputs"] == {}
            assert row["error"] and "\n" not in row["error"] and len(row["error"]) > 10, row
            assert not os.path.exists(os.path.join(out, row["name"] + ".vdb"))
        else:
            assert row["status"] == "done" and row["triangles"] == 20 * 4 ** 3 and row["worker"].startswith("tcp://")
            assert len(row["hash"]) == 64 and row["seconds"] > 0


def test_samples_hold_the_signed_distances(first_run, meshes):
    out, _ = first_run
    for name in ("sphere00", "sphere17"):
        radius, centre = meshes[1][name]
        s = np.load(os.path.join(out, name + ".npz"))
        for kind in ("uniform", "near"):
            points, sdf = s[kind + "_points"], s[kind + "_sdf"]
            assert points.shape == (200, 3) and sdf.shape == (200,)
            analytic = np.linalg.norm(points - centre, axis=1) - radius
            # The mesh lies inside the sphere by at most its sagitta (~0.005 radius at 3 levels).
            assert np.max(np.abs(sdf - analytic)) < 0.01 * radius
        # Near points lie in the band (3 voxels of 2 radius / RES) jittered by up to 3 voxels more.
        assert np.max(np.abs(s["near_sdf"])) < 2 * (2 * radius * 3 / RES)
        assert np.mean(s["uniform_sdf"] > 0) > 0.3


def test_rerun_bakes_nothing_and_a_changed_mesh_again(first_run, meshes, client, tmp_path):
    out, _ = first_run
    good = sorted(str(p) for p in meshes[0].glob("sphere*.obj"))
    mtimes = {f: os.stat(os.path.join(out, f)).st_mtime_ns for f in os.listdir(out) if f.endswith(".vdb")}
    summary = batch.run(good, out, client=client, res=RES, band=BAND, samples=200)
    assert (summary["done"], summary["cached"], summary["failed"]) == (0, GOOD, 0)
    assert mtimes == {f: os.stat(os.path.join(out, f)).st_mtime_ns for f in os.listdir(out) if f.endswith(".vdb")}
    # Other settings are another hash: baked again.
    changed = batch.run(good[:2], out, client=client, res=RES + 8, band=BAND, samples=200)
    assert (changed["done"], changed["cached"]) == (2, 0)
    check_consistent(out)


def test_a_killed_worker_loses_nothing(meshes, tmp_path):
    out = str(tmp_path / "out")
    good = sorted(str(p) for p in meshes[0].glob("sphere*.obj"))[:16]
    killed = []
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as c:
        with distributed.Client(c) as cl:
            pids = cl.run(os.getpid)

            def kill_one(row):
                if not killed:  # after the first item, while the others run or wait on both workers
                    address, pid = sorted(pids.items())[0]
                    os.kill(pid, signal.SIGKILL)
                    killed.append(address)
            summary = batch.run(good, out, client=cl, res=48, band=BAND, on_row=kill_one)
    assert killed
    assert (summary["done"], summary["failed"]) == (16, 0)
    rows = check_consistent(out)
    assert sorted(r["name"] for r in rows) == sorted(os.path.basename(p)[:-4] for p in good)


def test_ctrl_c_leaves_a_consistent_manifest_and_the_rerun_finishes(meshes, client, tmp_path):
    out = str(tmp_path / "out")
    good = sorted(str(p) for p in meshes[0].glob("sphere*.obj"))[:24]
    env = dict(os.environ)
    proc = subprocess.Popen([sys.executable, "-m", "rtsdf.batch", *good, "-o", out, "--workers", "2",
                             "--res", "56", "--band", str(BAND)], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    manifest = os.path.join(out, "manifest.jsonl")
    deadline = time.monotonic() + 90
    while time.monotonic() < deadline and proc.poll() is None:
        if os.path.exists(manifest) and len(open(manifest).readlines()) >= 3:
            break
        time.sleep(0.05)
    assert proc.poll() is None, proc.communicate()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "interrupted" in err
    first = check_consistent(out)
    finished = {r["name"] for r in first if r["status"] == "done"}
    assert 3 <= len(finished) < 24
    summary = batch.run(good, out, client=client, res=56, band=BAND)
    assert (summary["cached"], summary["done"], summary["failed"]) == (len(finished), 24 - len(finished), 0)
    rows = check_consistent(out)
    done = [r["name"] for r in rows if r["status"] == "done"]
    assert len(done) == len(set(done)) == 24  # nothing baked twice


def test_tiled_bake_equals_the_whole_one(client, tmp_path):
    scene = os.path.join(DATA, "scenes", "bunny.json")
    whole = str(tmp_path / "whole.vdb")
    rtsdf.bake(scene, method="exact", res=64, band=0.1).write(whole)
    for tiles in (3, 8, 16):  # 16 slabs of a grid 9 leaves long: some tiles are empty
        out = str(tmp_path / f"tiles{tiles}")
        summary = batch.run([scene], out, client=client, res=64, band=0.1, tiles=tiles)
        assert summary["done"] == 1
        (row,) = rows_of(out)
        assert row["tiles"] == tiles and row["active_voxels"] > 1000
        assert rtsdf.count_different_values(whole, os.path.join(out, "bunny.vdb")) == 0
    # The comparison sees a difference: one tile alone is not the whole bake.
    rtsdf.bake_tile(scene, str(tmp_path / "one.vdb"), 1, 3, res=64, band=0.1)
    assert rtsdf.count_different_values(whole, str(tmp_path / "one.vdb")) > 1000


def test_a_manifest_gives_per_item_settings_and_names(meshes, client, tmp_path):
    listing = tmp_path / "list.jsonl"
    rel = os.path.relpath(meshes[0], tmp_path)
    listing.write_text(json.dumps({"input": f"{rel}/sphere03.obj", "name": "fine", "res": 40}) + "\n\n" +
                       json.dumps({"input": f"{rel}/sphere04.obj", "samples": 50, "sign": "winding"}) + "\n")
    out = str(tmp_path / "out")
    summary = batch.run([str(listing), str(meshes[0] / "sphere0[5-6].obj")], out, client=client, res=RES, band=BAND)
    assert (summary["done"], summary["failed"]) == (4, 0)
    rows = {r["name"]: r for r in check_consistent(out)}
    assert sorted(rows) == ["fine", "sphere04", "sphere05", "sphere06"]
    assert rows["fine"]["settings"]["res"] == 40 and rows["sphere05"]["settings"]["res"] == RES
    assert rows["sphere04"]["settings"]["sign"] == "winding" and set(rows["sphere04"]["outputs"]) == {"vdb", "npz"}
    assert pyopenvdb.read(os.path.join(out, "fine.vdb"), "surface").evalActiveVoxelBoundingBox()[1][0] > \
        pyopenvdb.read(os.path.join(out, "sphere05.vdb"), "surface").evalActiveVoxelBoundingBox()[1][0]
    listing.write_text('{"no input": 1}\n')
    with pytest.raises(ValueError, match="list.jsonl:1"):
        batch.run([str(listing)], out, client=client)


def test_a_task_carries_the_mesh_to_a_worker_that_does_not_see_it(meshes, tmp_path):
    source = meshes[0] / "sphere05.obj"
    (item,) = batch.make_items([str(source)], {"method": "exact", "res": RES, "band": BAND}, 0, ship=True)
    assert item["bytes"] == source.read_bytes()
    item["path"] = str(tmp_path / "elsewhere" / "sphere05.obj")  # not on this worker
    result = batch.bake_item(item)
    assert result["status"] == "done", result
    assert result["triangles"] == 20 * 4 ** 3 and len(result["vdb"]) > 1000
    (bad,) = batch.make_items([str(meshes[0] / "bad_nan.obj")], {"method": "exact", "res": RES, "band": BAND}, 0,
                              ship=True)
    bad["path"] = str(tmp_path / "elsewhere" / "bad_nan.obj")
    failed = batch.bake_item(bad)
    assert failed["status"] == "failed" and "non-finite" in failed["error"]
    assert str(meshes[0] / "bad_nan.obj") in failed["error"]  # the input's name, not the worker's copy
    (local,) = batch.make_items([str(source)], {"res": RES}, 0)
    assert local["bytes"] is None  # a local cluster reads the file itself


def test_bad_settings_are_refused_before_any_work(tmp_path):
    with pytest.raises(ValueError, match="exact"):
        batch.run([os.path.join(DATA, "meshes", "bunny.obj")], str(tmp_path), method="openvdb", tiles=2)
    r = subprocess.run([sys.executable, "-m", "rtsdf.batch", "x.obj", "-o", str(tmp_path), "--workers", "0"],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "--workers 0 must be at least 1" in r.stderr
    with pytest.raises(rtsdf.SettingError, match="tile"):
        rtsdf.bake_tile(os.path.join(DATA, "meshes", "bunny.obj"), str(tmp_path / "t.vdb"), 3, 3)


def test_the_workers_bakes_are_quiet_and_the_batch_reports_each_item_once(tmp_path):
    folder = tmp_path / "four"
    generate(folder, good=4)
    good = [str(folder / f"sphere{i:02d}.obj") for i in range(4)]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    r = subprocess.run([sys.executable, "-m", "rtsdf.batch", *good, "-o", str(tmp_path / "out"), "--workers", "2",
                        "--res", str(RES), "--band", BAND], env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    # The batch's own progress: one line per item and a summary; nothing from the bakes inside the workers.
    assert "exact SDF" not in r.stderr and " done in " not in r.stderr, r.stderr
    assert sum("done sphere" in line for line in r.stderr.splitlines()) == 4, r.stderr
