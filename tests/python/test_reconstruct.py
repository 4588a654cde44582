# levelfuse.reconstruct: the converter's reconstruction from Python.
import json
import time

import numpy as np
import pytest

import levelfuse
from conftest import run_cli, shared, sphere_scans


def test_the_torus_from_python_gives_the_converters_bytes(cli, torus_scans, tmp_path):
    run_cli(cli, "reconstruct", torus_scans, "-o", tmp_path / "cli.vdb", "--mesh", tmp_path / "cli.ply",
            "--preview", tmp_path / "cli.png", "--quiet")
    result = levelfuse.reconstruct(str(torus_scans))
    result.write_vdb(str(tmp_path / "python.vdb"))
    result.write_mesh(str(tmp_path / "python.ply"))
    result.write_preview(str(tmp_path / "python.png"))
    for name in ("vdb", "ply", "png"):
        assert (tmp_path / f"python.{name}").read_bytes() == (tmp_path / f"cli.{name}").read_bytes(), name
    assert result.vdb_bytes() == (tmp_path / "cli.vdb").read_bytes()


def test_the_bunny_from_python_gives_the_converters_bytes(cli, tmp_path):
    bunny = shared("stanford", "bunny", "bun.conf")
    run_cli(cli, "reconstruct", bunny, "-o", tmp_path / "cli.vdb", "--quiet")
    result = levelfuse.reconstruct(str(bunny))
    assert result.vdb_bytes() == (tmp_path / "cli.vdb").read_bytes()


def test_the_summary_says_what_the_converters_json_says(cli, torus_scans, tmp_path):
    cli_summary = json.loads(run_cli(cli, "reconstruct", torus_scans, "-o", tmp_path / "t.vdb", "--json").stdout)
    summary = levelfuse.reconstruct(torus_scans).summary
    for key in ("scans", "points", "readings", "voxel_size", "levels", "beta", "epsilon", "narrow_band_voxels"):
        assert summary[key] == cli_summary[key], key
    assert [g["iterations"] for g in summary["grids"]] == [g["iterations"] for g in cli_summary["grids"]]
    for key in ("points", "mean", "median", "p90", "within_voxel"):
        assert summary["fit"][key] == pytest.approx(cli_summary["fit"][key], rel=1e-12), key
    assert summary["method"] == "evolution" and summary["scene"] is False
    # Where the time went: the reconstruction's phases, in the converter's among its own.
    reconstruction = [p["name"] for p in summary["phases"]]
    assert reconstruction[:2] == ["linear solution", "evolution"] and "surface weight" in reconstruction
    phases = [p["name"] for p in cli_summary["phases"]]
    assert phases[0] == "loading" and phases[-1] == "writing"
    assert [name for name in phases if name in reconstruction] == reconstruction
    assert all(p["seconds"] >= 0 and p["cpu_seconds"] >= 0 for p in cli_summary["phases"])
    assert sum(p["seconds"] for p in cli_summary["phases"]) <= cli_summary["seconds"] + 0.01


def test_range_maps_from_numpy_reconstruct_a_sphere():
    result = levelfuse.reconstruct(sphere_scans(noise=0.01), voxel_size=0.05)
    coords, values = result.grid.active_voxels()
    points = result.grid.index_to_world(coords[np.abs(values) < 0.5 * 0.05])
    radii = np.linalg.norm(points, axis=1)
    assert abs(np.mean(radii) - 1.0) < 0.03
    mesh = result.mesh()
    assert mesh.vertices.dtype == np.float32 and mesh.vertices.shape[1] == 3
    assert mesh.triangles.dtype == np.uint32 and mesh.triangles.max() < len(mesh.vertices)
    assert mesh.volume == pytest.approx(4.0 / 3.0 * np.pi, rel=0.05)
    assert result.summary["inputs"] == ["6 range maps from Python"]
    assert result.grid.metadata["levelfuse_inputs"] == "6 range maps from Python"


def test_every_option_is_a_keyword():
    maps = sphere_scans()
    result = levelfuse.reconstruct(maps, voxel_size=0.1, levels=2, beta=0.5, epsilon=0.05, window="binary",
                                   data_term="per_map", tolerance=0.1, patience=4, drift=0.05, min_iterations=2,
                                   max_iterations=20, name="ball", layers=2, max_step_change=0.4,
                                   curvature_step_limit=0.2, stiffness_step_limit=0.4, grain_size=2, fit=False)
    s = result.summary
    assert (s["voxel_size"], s["levels"], s["beta"], s["epsilon"]) == (0.1, 2, 0.5, 0.05)
    assert all(g["iterations"] <= 20 for g in s["grids"]) and "fit" not in s
    assert result.grid.name == "ball"
    with pytest.raises(TypeError, match="colour"):
        levelfuse.reconstruct(maps, colour="red")
    with pytest.raises(ValueError, match="window"):
        levelfuse.reconstruct(maps, window="box")
    with pytest.raises(TypeError, match="levels"):
        levelfuse.reconstruct(maps, levels=1.5)


def test_the_linear_solution():
    result = levelfuse.reconstruct(sphere_scans(), voxel_size=0.05, linear=True)
    assert result.summary["method"] == "linear" and result.summary["grids"] == []
    assert result.grid.metadata["levelfuse_method"] == "linear solution (zero set of g)"


def test_the_level_set_is_a_pyopenvdb_grid_sharing_the_result():
    pyopenvdb = pytest.importorskip("pyopenvdb")
    result = levelfuse.reconstruct(sphere_scans(), voxel_size=0.1)
    grid = result.level_set
    assert isinstance(grid, pyopenvdb.FloatGrid)
    assert grid.gridClass == pyopenvdb.GridClass.LEVEL_SET
    assert grid.activeVoxelCount() == result.grid.active_voxel_count
    grid["touched_in_pyopenvdb"] = 7  # the same grid, not a copy
    assert result.grid.metadata["touched_in_pyopenvdb"] == 7
    back = levelfuse.Grid.from_pyopenvdb(grid)
    assert back.active_voxel_count == grid.activeVoxelCount()
    assert isinstance(result.weight, pyopenvdb.FloatGrid) and result.weight.name == "weight"


def test_grids_cross_as_vdb_bytes_and_files(tmp_path):
    result = levelfuse.reconstruct(sphere_scans(), voxel_size=0.1)
    path = tmp_path / "ball.vdb"
    result.write_vdb(str(path))
    assert path.read_bytes() == result.vdb_bytes()
    grids = levelfuse.read_vdb(str(path))
    assert [g.name for g in grids] == ["surface", "weight"]
    coords, values = grids[0].active_voxels()
    original = result.grid.active_voxels()
    assert np.array_equal(coords, original[0]) and np.array_equal(values, original[1])
    samples = result.grid.sample(np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]]))
    assert samples[0] < 0 < samples[1]


def test_a_preview_is_an_rgb_array():
    picture = levelfuse.reconstruct(sphere_scans(), voxel_size=0.1).preview(width=64)
    assert picture.shape == (48, 64, 3) and picture.dtype == np.uint8
    assert len(np.unique(picture.reshape(-1, 3), axis=0)) > 10


def test_progress_is_called_at_each_stage_and_at_most_five_times_a_second():
    calls = []
    started = time.monotonic()
    levelfuse.reconstruct(sphere_scans(noise=0.02), voxel_size=0.04, progress=calls.append)
    seconds = time.monotonic() - started
    assert calls and calls[-1]["stage"] == "done"
    stages = {c["stage"] for c in calls}
    assert "evolving" in stages
    assert len(calls) <= 5 * seconds + 2 * len(stages) + 2


def test_a_callback_returning_false_cancels():
    seen = []

    def stop_when_evolving(p):
        seen.append(p["stage"])
        return p["stage"] != "evolving"

    with pytest.raises(levelfuse.Cancelled):
        levelfuse.reconstruct(sphere_scans(), voxel_size=0.05, progress=stop_when_evolving)
    assert seen[-1] == "evolving"


def test_a_callback_that_raises_stops_the_work_with_its_exception():
    class Enough(Exception):
        pass

    def fail(p):
        raise Enough(p["stage"])

    with pytest.raises(Enough):
        levelfuse.reconstruct(sphere_scans(), voxel_size=0.05, progress=fail)


def test_a_grid_that_would_not_fit_raises_insufficient_memory():
    with pytest.raises(levelfuse.InsufficientMemory, match="voxel") as raised:
        levelfuse.reconstruct(sphere_scans(), voxel_size=2e-5)
    assert isinstance(raised.value, MemoryError)


def test_unusable_options_raise_value_error_with_the_libraries_hint():
    with pytest.raises(ValueError, match="tolerance"):
        levelfuse.reconstruct(sphere_scans(), voxel_size=0.1, tolerance=-1.0)
    with pytest.raises(TypeError, match="scans"):
        levelfuse.reconstruct(42)
    with pytest.raises(ValueError, match="no scans"):
        levelfuse.reconstruct([])
