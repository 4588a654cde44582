# levelfuse's Python tests: where the module, the converter and the shared data are.
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

BUILD_PYTHON = os.environ.get("LEVELFUSE_PYTHON_DIR")
if BUILD_PYTHON:
    sys.path.insert(0, BUILD_PYTHON)

import levelfuse  # noqa: E402

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
SHARED_DATA = REPOSITORY.parent / "shared" / "data"


@pytest.fixture(scope="session")
def cli():
    """The levelfuse converter built beside the module."""
    path = os.environ.get("LEVELFUSE_CLI")
    if not path or not os.path.exists(path):
        pytest.skip("LEVELFUSE_CLI does not name the levelfuse converter")
    return path


def run_cli(cli, *args):
    return subprocess.run([cli, *map(str, args)], check=True, capture_output=True, text=True)


@pytest.fixture(scope="session")
def torus_scans(cli, tmp_path_factory):
    """Six noisy range scans of a torus (the paper's Fig. 10), as the quick start makes them."""
    folder = tmp_path_factory.mktemp("torus")
    run_cli(cli, "synth", "--shape", "torus", "--noise", "0.2", "-o", folder)
    return folder / "scans.json"


def shared(*parts):
    path = SHARED_DATA.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"{path} is not there (the shared data sit beside the repository)")
    return path


def rotation_with_axis(d):
    """A rotation whose third column (the map's rays) is the unit vector d."""
    d = np.asarray(d, dtype=float)
    helper = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    a = np.cross(helper, d)
    a /= np.linalg.norm(a)
    b = np.cross(d, a)
    return np.column_stack([a, b, d])


def sphere_scans(radius=1.0, pixels=48, noise=0.0, seed=0):
    """Six orthographic range maps of a sphere at the origin, one along each axis."""
    rng = np.random.default_rng(seed)
    pixel = 3.0 * radius / pixels
    coords = (np.arange(pixels) - (pixels - 1) / 2.0) * pixel
    x, y = np.meshgrid(coords, coords)
    inside = radius**2 - x**2 - y**2
    maps = []
    for axis in range(3):
        for sign in (1.0, -1.0):
            d = np.zeros(3)
            d[axis] = sign
            pose = np.eye(4)
            pose[:3, :3] = rotation_with_axis(d)
            pose[:3, 3] = -2.0 * radius * d
            readings = np.where(inside > 0, 2.0 * radius - np.sqrt(np.maximum(inside, 0.0)), np.nan)
            readings = readings + noise * rng.standard_normal(readings.shape)
            maps.append(levelfuse.RangeMap.orthographic(
                readings.astype(np.float32), pixel, pose, sigma=max(noise, 0.01 * radius),
                origin=(coords[0], coords[0], 0.0), name=f"view{len(maps)}"))
    return maps
