"""rtsdf.Mesh: triangles from numpy arrays, validated and repaired as a mesh file is, accepted wherever a scene or
mesh path is (ctest label python)."""
import os

import numpy as np
import pytest

import rtsdf

DATA = os.environ.get("RTSDF_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "data"))
BUNNY_OBJ = os.path.join(DATA, "meshes", "bunny.obj")


def read_obj(path):
    """The vertices and triangles of a triangle-only OBJ file, read here without the library."""
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            words = line.split()
            if words and words[0] == "v":
                vertices.append([float(x) for x in words[1:4]])
            elif words and words[0] == "f":
                assert len(words) == 4, "a polygon: this reader takes triangles only"
                faces.append([int(w.split("/")[0]) - 1 for w in words[1:]])
    return np.array(vertices, dtype=np.float64), np.array(faces, dtype=np.int64)


def write_binary_ply(path, vertices, faces):
    """A little-endian binary PLY: float32 vertices and int32 triangles, read back bit for bit (an OBJ's decimal
    text would leave the rounding to the reader's own parser)."""
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\nproperty float x\n"
              f"property float y\nproperty float z\nelement face {len(faces)}\n"
              "property list uchar int vertex_indices\nend_header\n")
    rows = np.zeros(len(faces), dtype=[("n", "u1"), ("v", "<i4", 3)])
    rows["n"], rows["v"] = 3, faces
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(vertices.astype("<f4").tobytes())
        f.write(rows.tobytes())


@pytest.fixture(scope="module")
def bunny_arrays(tmp_path_factory):
    """The bunny's vertices rounded to float32 (as rtsdf stores them) and its triangles, and the same as a file."""
    vertices, faces = read_obj(BUNNY_OBJ)
    vertices = vertices.astype(np.float32).astype(np.float64)
    path = tmp_path_factory.mktemp("bunny") / "bunny.ply"
    write_binary_ply(path, vertices, faces)
    return vertices, faces, str(path)


@pytest.fixture(scope="module")
def bunny_file_bake(bunny_arrays):
    return rtsdf.bake(bunny_arrays[2], method="exact", res=48, band=0.4)


def assert_same_field(a, b):
    assert a.values.shape == b.values.shape
    assert a.origin == b.origin and a.voxel_size == b.voxel_size
    assert np.array_equal(a.active, b.active)
    assert np.array_equal(a.values, b.values)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_bunny_from_arrays_equals_the_file_bake(bunny_arrays, bunny_file_bake, dtype):
    vertices, faces, _ = bunny_arrays
    mesh = rtsdf.Mesh(vertices.astype(dtype), faces.astype(np.int32), name="bunny")
    assert mesh.triangles == len(faces) - mesh.dropped_triangles and mesh.triangles > 1000
    assert "rtsdf.Mesh('bunny'" in repr(mesh)
    field = rtsdf.bake(mesh, method="exact", res=48, band=0.4)
    assert 1000 < field.active.sum()
    assert_same_field(field, bunny_file_bake)


@pytest.mark.parametrize("step", [3, 1])
def test_array_meshes_are_repaired_as_files_are(bunny_arrays, bunny_file_bake, tmp_path, step):
    """Every third triangle's corners reversed, or all of them (the closed bunny then faces inward): the array mesh
    and the same triangles' file are repaired alike, voxel for voxel, and both have the intact bunny's field."""
    vertices, faces, _ = bunny_arrays
    flipped = faces.copy()
    flipped[::step] = flipped[::step, ::-1]
    mesh = rtsdf.Mesh(vertices, flipped)
    assert mesh.watertight and mesh.reoriented_triangles == len(faces[::step]) - mesh.dropped_triangles
    field = rtsdf.bake(mesh, method="exact", res=48, band=0.4)
    path = tmp_path / "flipped.ply"
    write_binary_ply(path, vertices, flipped)
    assert_same_field(field, rtsdf.bake(str(path), method="exact", res=48, band=0.4))
    # The repair reverses corner order its own way, which changes the distances' float rounding alone.
    intact = bunny_file_bake
    assert np.array_equal(field.active, intact.active)
    assert np.array_equal(np.sign(field.values), np.sign(intact.values))
    assert np.max(np.abs(field.values - intact.values)) < 1e-5 * intact.voxel_size


def test_a_mesh_goes_wherever_a_path_goes(bunny_arrays):
    vertices, faces, ply = bunny_arrays
    mesh = rtsdf.Mesh(vertices, faces)
    rng = np.random.default_rng(5)
    points = rng.uniform(vertices.min(0), vertices.max(0), size=(500, 3))
    assert np.array_equal(rtsdf.distance(mesh, points), rtsdf.distance(ply, points))
    pipe = rtsdf.Pipeline(mesh, frames=1, coarse=16, fine=32, band=0.8, refine="closest", rays=0)
    pipe.frame(0.0)
    assert pipe.fine().active.sum() > 100 and "rtsdf.Pipeline(" in repr(pipe)


def test_bad_arrays_are_refused_naming_the_argument():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    assert rtsdf.Mesh(v, f).watertight
    with pytest.raises(TypeError, match="vertices: dtype int64"):
        rtsdf.Mesh(v.astype(np.int64), f)
    with pytest.raises(ValueError, match=r"vertices: shape \(4, 2\)"):
        rtsdf.Mesh(v[:, :2], f)
    with pytest.raises(TypeError, match="faces: dtype float64"):
        rtsdf.Mesh(v, f.astype(np.float64))
    with pytest.raises(ValueError, match=r"faces: shape \(12\)"):
        rtsdf.Mesh(v, f.ravel())
    with pytest.raises(ValueError, match="faces: row 1 uses vertex 4"):
        rtsdf.Mesh(v, np.array([[0, 1, 2], [1, 2, 4]]))
    with pytest.raises(ValueError, match="faces: row 0 uses vertex -1"):
        rtsdf.Mesh(v, np.array([[0, 1, -1]]))
    nan = v.copy()
    nan[2, 1] = np.nan
    with pytest.raises(ValueError, match="vertices: row 2 is not finite"):
        rtsdf.Mesh(nan, f)
    with pytest.raises(rtsdf.Error, match="zero area"):
        rtsdf.Mesh(v, np.array([[0, 0, 1]]))
    with pytest.raises(TypeError, match=r"scene: expected an rtsdf.Scene, an rtsdf.Mesh or a path, not tuple"):
        rtsdf.bake((v, f))
