"""Field.sample and Field.gradient (OpenVDB's trilinear sampler and its gradient), in the points' dtype, and the
writes' extension check (ctest label python)."""
import os

import numpy as np
import pytest

import rtsdf

DATA = os.environ.get("RTSDF_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "data"))


@pytest.fixture(scope="module")
def field():
    return rtsdf.bake(os.path.join(DATA, "scenes", "bunny.json"), method="exact", res=40, band=0.15)


def centres(field, index):
    return np.array(field.origin) + (np.asarray(index, dtype=np.float64) + 0.5) * field.voxel_size


def test_samples_at_voxel_centres_are_the_stored_values(field):
    values, active = field.values, field.active
    index = np.argwhere(np.ones(values.shape, bool))  # every voxel, band and background
    stored = values[tuple(index.T)]
    s = field.sample(centres(field, index))
    assert s.dtype == np.float64 and s.shape == (len(index),)
    assert np.max(np.abs(s - stored)) < 1e-6
    s32 = field.sample(centres(field, index).astype(np.float32))
    assert s32.dtype == np.float32 and np.max(np.abs(s32 - stored)) < 1e-5
    assert active.sum() > 1000 and np.any(stored < 0) and np.any(stored > 0)
    # Any leading shape: (..., 3) -> (...).
    grid = centres(field, np.argwhere(active)[:12]).reshape(3, 4, 3)
    assert field.sample(grid).shape == (3, 4) and field.gradient(grid).shape == (3, 4, 3)


def test_between_centres_samples_interpolate_trilinearly(field):
    index = np.argwhere(field.active)[::37]
    inner = index[np.all((index > 0) & (index < np.array(field.values.shape) - 1), axis=1)]
    halfway = field.sample(centres(field, inner + [0.5, 0.0, 0.0]))
    v = field.values
    expected = 0.5 * (v[tuple(inner.T)] + v[tuple((inner + [1, 0, 0]).T)])
    assert np.max(np.abs(halfway - expected)) < 1e-6


def test_gradients_match_finite_differences_of_sample(field):
    rng = np.random.default_rng(11)
    active = field.active
    # Cells whose eight corners are all in the band: the interpolant is one trilinear patch there.
    corners = active[:-1, :-1, :-1] & active[1:, :-1, :-1] & active[:-1, 1:, :-1] & active[:-1, :-1, 1:] & \
        active[1:, 1:, :-1] & active[1:, :-1, 1:] & active[:-1, 1:, 1:] & active[1:, 1:, 1:]
    cells = np.argwhere(corners)
    cells = cells[rng.choice(len(cells), size=min(2000, len(cells)), replace=False)]
    points = centres(field, cells + rng.uniform(0.25, 0.75, size=cells.shape))
    g = field.gradient(points)
    assert g.dtype == np.float64 and g.shape == points.shape
    h = 0.2 * field.voxel_size  # stays within the cell: the difference of a trilinear patch is exact
    fd = np.stack([(field.sample(points + h * e) - field.sample(points - h * e)) / (2 * h) for e in np.eye(3)],
                  axis=1)
    assert np.max(np.abs(g - fd)) < 1e-3
    # A distance field: gradients of about unit length.
    assert 0.8 < np.median(np.linalg.norm(g, axis=1)) < 1.2
    assert field.gradient(points.astype(np.float32)).dtype == np.float32


def test_outside_the_band_samples_are_the_background(field):
    far = np.array([[100.0, 100.0, 100.0], [np.nan, 0.0, 0.0]])
    s = field.sample(far)
    assert s[0] == pytest.approx(field.band) and np.isnan(s[1])
    assert np.array_equal(field.gradient(far[:1]), np.zeros((1, 3)))
    with pytest.raises(ValueError, match=r"points: the last axis"):
        field.sample(np.zeros((4, 2)))


def test_write_refuses_another_extension(field, tmp_path):
    for name in ("x.npy", "x.vdb.tmp", "x"):
        with pytest.raises(rtsdf.Error, match=r"\.vdb"):
            field.write(str(tmp_path / name))
        assert not (tmp_path / name).exists()
    field.write(tmp_path / "x.vdb")
    assert (tmp_path / "x.vdb").stat().st_size > 0
