# levelfuse.reconstruct: the converter's reconstruction from Python.
import json
import re
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
    # One summary, made by the library for both: the same keys (the converter also measures a
    # synthetic scene against its truth), the same values but the run's own.
    assert cli_summary.keys() - summary.keys() == {"truth"} and summary.keys() <= cli_summary.keys()
    for key in ("scans", "points", "readings", "voxel_size", "levels", "beta", "epsilon", "engine", "scene",
                "narrow_band_voxels", "peak_engine_bytes", "data_term_bytes", "triangles", "trimmed_unseen"):
        assert summary[key] == cli_summary[key], key
    assert summary["outputs"] == {"vdb": None, "mesh": None, "preview": None}
    assert cli_summary["outputs"] == {"vdb": str(tmp_path / "t.vdb"), "mesh": None, "preview": None}
    assert [g["iterations"] for g in summary["grids"]] == [g["iterations"] for g in cli_summary["grids"]]
    assert summary["fit"].keys() == cli_summary["fit"].keys()
    for key in ("points", "stride", "mean", "median", "p90", "within_voxel"):
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


# Each keyword of levelfuse.reconstruct, set away from its default, and what it must change: the
# sphere is reconstructed with `settings`, then again with the keyword set to `value` as well, and
# `effect(before, after)` asserts what the keyword does to the result. A keyword the module dropped
# would leave the two runs alike, and its case would fail.
NEVER_STOPPING = dict(tolerance=1e-9, drift=1e-12)  # runs every iteration it may
SIX_ITERATIONS = dict(NEVER_STOPPING, min_iterations=6, max_iterations=6)


def grid_reports(result, key):
    return [g[key] for g in result.summary["grids"]]


def level_set_differs(before, after):
    b, a = before.grid.active_voxels(), after.grid.active_voxels()
    return not (np.array_equal(b[0], a[0]) and np.array_equal(b[1], a[1]))


def voxel_size_effect(before, after):
    assert after.summary["voxel_size"] == 0.125 and after.grid.voxel_size == pytest.approx(0.125)
    assert grid_reports(after, "voxel_size") == [0.125] and grid_reports(before, "voxel_size") == [0.1]


def levels_effect(before, after):
    assert after.summary["levels"] == 2 and before.summary["levels"] == 1
    assert grid_reports(after, "voxel_size") == [0.2, 0.1]


def beta_effect(before, after):
    # The surface-area prior pulls a sphere in by about 2 beta / R voxels: 0.8 voxel of 10.
    assert after.summary["beta"] == 4.0 and before.summary["beta"] == 0.5
    assert after.mesh().volume < 0.9 * before.mesh().volume


def epsilon_effect(before, after):
    assert after.summary["epsilon"] == 0.2 and after.grid.metadata["levelfuse_epsilon"] == 0.2
    assert level_set_differs(before, after)


def window_effect(before, after):
    assert before.grid.metadata["levelfuse_window"] == "gaussian"
    assert after.grid.metadata["levelfuse_window"] == "binary"
    assert level_set_differs(before, after)


def data_term_from_grids(before, after):
    # Six maps sample the data term map by map unless it is asked from grids.
    assert before.grid.metadata["levelfuse_data_term"] == "maps"
    assert after.grid.metadata["levelfuse_data_term"] == "grids"
    assert level_set_differs(before, after)


def data_term_per_map(before, after):
    # Thirty-six maps (more than 32) sample it from grids unless it is asked map by map.
    assert before.grid.metadata["levelfuse_data_term"] == "grids"
    assert after.grid.metadata["levelfuse_data_term"] == "maps"


def tolerance_effect(before, after):
    assert grid_reports(before, "converged") == [True] and grid_reports(before, "iterations") == [4]
    assert grid_reports(after, "converged") == [False] and grid_reports(after, "iterations") == [30]


def patience_effect(before, after):
    # Settling is judged every `patience` iterations, once the speed has not fallen for as many.
    assert grid_reports(before, "settled") == [True] and grid_reports(after, "settled") == [True]
    (b,), (a,) = grid_reports(before, "iterations"), grid_reports(after, "iterations")
    assert b % 8 == 0 and a % 20 == 0 and a > b


def drift_effect(before, after):
    # The noiseless sphere drifts less than the default 0.025 voxel an iteration, never less than 1e-12.
    assert grid_reports(before, "settled") == [True] and grid_reports(before, "iterations")[0] < 60
    assert grid_reports(after, "settled") == [False] and grid_reports(after, "iterations") == [60]


def min_iterations_effect(before, after):
    # A tolerance nothing misses converges at the first iteration allowed.
    assert grid_reports(before, "iterations") == [4] and grid_reports(after, "iterations") == [9]
    assert grid_reports(after, "converged") == [True]


def max_iterations_effect(before, after):
    # A limit below the default minimum (4) lowers the minimum, as the converter's does.
    assert grid_reports(before, "iterations") == [300] and grid_reports(after, "iterations") == [3]


def name_effect(before, after):
    assert before.grid.name == "surface" and after.grid.name == "ball" and after.weight_grid.name == "weight"


def layers_effect(before, after):
    # Two more layers about the same active set: the band grows by about twice the active set.
    assert grid_reports(after, "active_set_voxels") == grid_reports(before, "active_set_voxels")
    (b,), (a,), (active,) = (grid_reports(before, "band_voxels"), grid_reports(after, "band_voxels"),
                             grid_reports(after, "active_set_voxels"))
    assert a - b == pytest.approx(2 * active, rel=0.1)
    assert after.summary["engine"]["layers"] == 3


def step_limit_effect(keyword, value):
    def effect(before, after):
        # A lower limit on the time step: less time simulated in the same six iterations.
        assert grid_reports(before, "iterations") == grid_reports(after, "iterations") == [6]
        assert grid_reports(after, "simulated_time")[0] < 0.9 * grid_reports(before, "simulated_time")[0]
        assert after.summary["engine"][keyword] == value
    return effect


def grain_size_effect(before, after):
    # Leaf nodes per parallel task: the engine's, reported; the result is the same byte for byte.
    assert before.summary["engine"]["grain_size"] == 4 and after.summary["engine"]["grain_size"] == 0
    assert after.vdb_bytes() == before.vdb_bytes()


def linear_effect(before, after):
    assert before.summary["method"] == "evolution" and after.summary["method"] == "linear"
    assert after.summary["grids"] == [] and len(before.summary["grids"]) == 1


def fit_effect(before, after):
    assert before.summary["fit"] is not None and after.summary["fit"] is None


def inputs_effect(before, after):
    assert before.summary["inputs"] == ["6 range maps from Python"]
    assert after.summary["inputs"] == ["ball.json"] and after.grid.metadata["levelfuse_inputs"] == "ball.json"


KEYWORD_EFFECTS = [
    pytest.param("voxel_size", 0.125, voxel_size_effect, {}, id="voxel_size"),
    pytest.param("levels", 2, levels_effect, {}, id="levels"),
    pytest.param("beta", 4.0, beta_effect, {}, id="beta"),
    pytest.param("epsilon", 0.2, epsilon_effect, {}, id="epsilon"),
    pytest.param("window", "binary", window_effect, {}, id="window"),
    pytest.param("data_term", "grids", data_term_from_grids, {}, id="data_term-grids"),
    pytest.param("data_term", "per_map", data_term_per_map, {"copies": 6}, id="data_term-per_map"),
    pytest.param("tolerance", 1e-9, tolerance_effect, dict(drift=1e-12, max_iterations=30), id="tolerance"),
    pytest.param("patience", 20, patience_effect, dict(tolerance=1e-9, drift=1e3, max_iterations=200),
                 id="patience"),
    pytest.param("drift", 1e-12, drift_effect, dict(tolerance=1e-9, patience=2, max_iterations=60), id="drift"),
    pytest.param("min_iterations", 9, min_iterations_effect, dict(tolerance=1e3), id="min_iterations"),
    pytest.param("max_iterations", 3, max_iterations_effect, NEVER_STOPPING, id="max_iterations"),
    pytest.param("name", "ball", name_effect, {}, id="name"),
    pytest.param("layers", 3, layers_effect, {}, id="layers"),
    pytest.param("max_step_change", 0.05, step_limit_effect("max_step_change", 0.05), SIX_ITERATIONS,
                 id="max_step_change"),
    pytest.param("curvature_step_limit", 0.02, step_limit_effect("curvature_step_limit", 0.02), SIX_ITERATIONS,
                 id="curvature_step_limit"),
    pytest.param("stiffness_step_limit", 0.05, step_limit_effect("stiffness_step_limit", 0.05), SIX_ITERATIONS,
                 id="stiffness_step_limit"),
    pytest.param("grain_size", 0, grain_size_effect, {}, id="grain_size"),
    pytest.param("linear", True, linear_effect, {}, id="linear"),
    pytest.param("fit", False, fit_effect, {"fit": True}, id="fit"),
    pytest.param("inputs", ["ball.json"], inputs_effect, {}, id="inputs"),
]


@pytest.mark.parametrize("keyword, value, effect, settings", KEYWORD_EFFECTS)
def test_each_keyword_changes_what_it_sets(keyword, value, effect, settings):
    settings = dict(settings)
    maps = sphere_scans() * settings.pop("copies", 1)
    run = {"voxel_size": 0.1, "fit": False, **settings}
    assert run.get(keyword) != value
    before = levelfuse.reconstruct(maps, **run)
    after = levelfuse.reconstruct(maps, **{**run, keyword: value})
    effect(before, after)


def test_every_documented_keyword_has_its_effect_checked():
    doc = levelfuse.reconstruct.__doc__
    block = doc[doc.index("Keywords"):doc.index("and for paths")].split("\n", 1)[1]
    documented = set(re.findall(r"\b([a-z_]+)(?==|,|\n| \()", block))
    checked = {case.values[0] for case in KEYWORD_EFFECTS} | {"memory_budget"}
    assert documented == checked


def test_memory_budget_refuses_what_would_not_fit():
    maps = sphere_scans()
    levelfuse.reconstruct(maps, voxel_size=0.1, fit=False, memory_budget=2**30)
    with pytest.raises(levelfuse.InsufficientMemory, match="more than the 64 KiB levelfuse may use"):
        levelfuse.reconstruct(maps, voxel_size=0.1, fit=False, memory_budget=65536)
    with pytest.raises(TypeError, match="memory_budget"):
        levelfuse.reconstruct(maps, memory_budget="a lot")
    with pytest.raises(ValueError, match="memory_budget"):
        levelfuse.reconstruct(maps, memory_budget=0)


def test_the_readers_take_the_memory_budget():
    frames = shared("7scenes")
    with pytest.raises(levelfuse.InputError, match="more than the 9.77 KiB levelfuse may use"):
        levelfuse.load_scans(str(frames), memory_budget=10000)
    with pytest.raises(levelfuse.InputError, match="more than the 9.77 KiB levelfuse may use"):
        levelfuse.reconstruct(str(frames), memory_budget=10000)


def test_keywords_refuse_what_they_cannot_take():
    maps = sphere_scans()
    with pytest.raises(TypeError, match="colour"):
        levelfuse.reconstruct(maps, colour="red")
    with pytest.raises(ValueError, match="window"):
        levelfuse.reconstruct(maps, window="box")
    with pytest.raises(ValueError, match="data_term"):
        levelfuse.reconstruct(maps, data_term="voxels")
    with pytest.raises(TypeError, match="levels"):
        levelfuse.reconstruct(maps, levels=1.5)
    with pytest.raises(ValueError, match="grain_size"):
        levelfuse.reconstruct(maps, grain_size=-1)
    with pytest.raises(ValueError, match="layers"):
        levelfuse.reconstruct(maps, voxel_size=0.1, layers=4)


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
