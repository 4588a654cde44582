# levelfuse.SparseField: the engine alone, with built-in speeds and forces from Python.
import math

import numpy as np
import pytest

import levelfuse


def ball_mask(radius=10, size=32):
    i, j, k = np.indices((size, size, size))
    c = (size - 1) / 2.0
    return (i - c) ** 2 + (j - c) ** 2 + (k - c) ** 2 <= radius**2


def mean_radius(field):
    coords, x, normals = field.active_points()
    centre = (32 - 1) / 2.0 * field.voxel_size
    return float(np.mean(np.linalg.norm(x - centre, axis=1)))


def test_a_mask_becomes_a_level_set():
    field = levelfuse.SparseField.from_mask(ball_mask(), voxel_size=0.5)
    assert field.voxel_size == 0.5 and field.layers == 2
    assert field.stats["active_set_voxels"] > 1000
    assert mean_radius(field) == pytest.approx(5.0, abs=0.3)
    assert field.grid().grid_class == "level set"


def test_curvature_flow_shrinks_a_sphere_as_the_paper_says():
    field = levelfuse.SparseField.from_mask(ball_mask(radius=12), voxel_size=1.0)
    r0 = mean_radius(field)
    field.advance(10.0, beta=1.0)
    # R(t)^2 = R0^2 - 4 beta t
    assert mean_radius(field) == pytest.approx(math.sqrt(r0**2 - 40.0), abs=0.3)


def test_a_force_from_python_is_called_once_per_step_with_every_active_point():
    field = levelfuse.SparseField.from_mask(ball_mask(), voxel_size=1.0)
    calls = []

    def outward(x, n):
        calls.append((x.shape, n.shape))
        return np.ones(len(x))

    before = field.stats["active_set_voxels"]
    result = field.step(force=outward)
    assert calls == [((before, 3), (before, 3))]
    assert result["dt"] > 0


def test_a_constant_force_from_python_moves_the_surface_as_the_built_in_one():
    built_in = levelfuse.SparseField.from_mask(ball_mask(), voxel_size=1.0)
    from_python = levelfuse.SparseField.from_mask(ball_mask(), voxel_size=1.0)
    for _ in range(5):
        built_in.step(force=0.7, beta=0.3)
        from_python.step(force=lambda x, n: np.full(len(x), 0.7), beta=0.3)
    a, b = built_in.grid().active_voxels(), from_python.grid().active_voxels()
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


def test_a_force_sees_subcell_positions_and_outward_normals():
    field = levelfuse.SparseField.from_mask(ball_mask(), voxel_size=1.0)
    coords, x, normals = field.active_points()
    centre = np.full(3, 15.5)
    radial = (x - centre) / np.linalg.norm(x - centre, axis=1)[:, None]
    assert np.mean(np.sum(radial * normals, axis=1)) > 0.95


def test_the_engine_takes_pyopenvdb_level_sets():
    pyopenvdb = pytest.importorskip("pyopenvdb")
    sphere = pyopenvdb.createLevelSetSphere(radius=2.0, voxelSize=0.1)
    field = levelfuse.SparseField(sphere)
    field.advance(0.5, force=-0.5)
    out = field.level_set()
    assert isinstance(out, pyopenvdb.FloatGrid)
    assert 1.6 < mean_radius_of_grid(out) < 1.8


def mean_radius_of_grid(grid):
    g = levelfuse.Grid.from_pyopenvdb(grid)
    coords, values = g.active_voxels()
    near = np.abs(values) < 0.5 * g.voxel_size
    return float(np.mean(np.linalg.norm(g.index_to_world(coords[near]), axis=1)))


def test_bad_engine_arguments():
    field = levelfuse.SparseField.from_mask(ball_mask(), voxel_size=1.0)
    with pytest.raises(ValueError, match="nothing moves"):
        field.step()
    with pytest.raises(ValueError, match="speeds"):
        field.step(force=lambda x, n: np.ones(3))
    with pytest.raises(ValueError, match="not finite"):
        field.step(force=lambda x, n: np.full(len(x), np.nan))
    with pytest.raises(ZeroDivisionError):
        field.step(force=lambda x, n: 1 / 0)
    with pytest.raises(TypeError, match="bool"):
        levelfuse.SparseField.from_mask(np.zeros((4, 4, 4), dtype=np.uint8))
    with pytest.raises(ValueError, match="empty"):
        levelfuse.SparseField.from_mask(np.zeros((4, 4, 4), dtype=bool))
    with pytest.raises(TypeError, match="pyopenvdb"):
        levelfuse.SparseField("sphere")
