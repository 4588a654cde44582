# Colour from Python: scans painted in two halves give a coloured surface,
# mesh and .vdb, the converter's bytes.
import numpy as np
import pytest

import levelfuse
from conftest import run_cli

RED, BLUE = (200, 40, 30), (30, 60, 200)


@pytest.fixture(scope="module")
def painted_sphere(cli, tmp_path_factory):
    """The unit sphere from six views, its upper half red and its lower half blue."""
    folder = tmp_path_factory.mktemp("painted")
    run_cli(cli, "synth", "--shape", "sphere", "--resolution", "80", "--paint", "halves", "-o", folder)
    return folder / "scans.json"


def test_a_painted_sphere_gives_the_converters_coloured_bytes(cli, painted_sphere, tmp_path):
    run_cli(cli, "reconstruct", painted_sphere, "-o", tmp_path / "cli.vdb", "--mesh", tmp_path / "cli.ply",
            "--preview", tmp_path / "cli.png", "--quiet")
    result = levelfuse.reconstruct(str(painted_sphere))
    result.write_mesh(str(tmp_path / "python.ply"))
    result.write_preview(str(tmp_path / "python.png"))
    assert result.vdb_bytes() == (tmp_path / "cli.vdb").read_bytes()
    for name in ("ply", "png"):
        assert (tmp_path / f"python.{name}").read_bytes() == (tmp_path / f"cli.{name}").read_bytes(), name


def test_each_vertex_has_the_colour_of_its_half(painted_sphere):
    result = levelfuse.reconstruct(str(painted_sphere))
    mesh = result.mesh()
    assert mesh.colours.shape == (len(mesh.vertices), 3)
    assert mesh.colours.dtype == np.uint8
    z = mesh.vertices[:, 2]
    away = np.abs(z) > 5 * result.summary["voxel_size"]
    expected = np.where(z[:, None] > 0, np.array(RED), np.array(BLUE))
    assert np.all(np.abs(mesh.colours[away].astype(int) - expected[away]) <= 5)


def test_the_colour_grid_is_shared_with_pyopenvdb(painted_sphere):
    pytest.importorskip("pyopenvdb")
    colour = levelfuse.reconstruct(str(painted_sphere)).colour
    assert colour.name == "Cd"
    assert colour.activeVoxelCount() > 10000
    value, active = colour.getConstAccessor().probeValue((0, 0, 0))
    assert not active and value == pytest.approx((0.5, 0.5, 0.5))  # the middle of the sphere: unseen grey


def test_scans_without_colour_give_none(torus_scans):
    result = levelfuse.reconstruct(str(torus_scans))
    assert result.colour is None
    assert result.mesh().colours is None
