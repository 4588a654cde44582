# Range maps from numpy and from files; every bad input gets a clear TypeError or ValueError.
import numpy as np
import pytest

import levelfuse
from conftest import shared

K = np.array([[525.0, 0.0, 319.5], [0.0, 525.0, 239.5], [0.0, 0.0, 1.0]])


def wall(shape=(48, 64), depth=2.0):
    return np.full(shape, depth, dtype=np.float32)


def test_a_depth_frame_from_float32_metres_or_uint16_units_is_the_same_map():
    metres = levelfuse.RangeMap.pinhole(wall(depth=1.5), K, np.eye(4))
    units = levelfuse.RangeMap.pinhole(np.full((48, 64), 1500, dtype=np.uint16), K, np.eye(4), depth_scale=0.001)
    assert metres.kind == "pinhole" and (metres.width, metres.height) == (64, 48)
    assert np.array_equal(metres.readings(), units.readings())
    assert metres.valid_count == 48 * 64


def test_no_reading_is_nan_zero_or_65535():
    depth = wall()
    depth[0, :5] = np.nan
    depth[1, :3] = 0.0
    assert levelfuse.RangeMap.pinhole(depth, K, np.eye(4)).valid_count == 48 * 64 - 8
    units = np.full((48, 64), 2000, dtype=np.uint16)
    units[0, :2] = 0
    units[0, 2:4] = 65535
    assert levelfuse.RangeMap.pinhole(units, K, np.eye(4)).valid_count == 48 * 64 - 4


def test_max_depth_drops_deeper_readings():
    depth = wall()
    depth[:10] = 5.0
    assert levelfuse.RangeMap.pinhole(depth, K, np.eye(4), max_depth=3.0).valid_count == 38 * 64


def test_poses_are_camera_to_world_with_column_vectors():
    pose = np.eye(4)
    pose[:3, 3] = [1.0, 2.0, 3.0]
    frame = levelfuse.RangeMap.pinhole(wall(), K, pose)
    assert frame.scanner_position == pytest.approx((1.0, 2.0, 3.0))
    assert np.allclose(frame.pose, pose)
    assert levelfuse.RangeMap.pinhole(wall(), (525.0, 525.0, 319.5, 239.5), pose).scanner_position == pytest.approx(
        (1.0, 2.0, 3.0))


@pytest.mark.parametrize("depth, error, message", [
    (np.zeros((48, 64), dtype=np.float64), TypeError, "float32"),
    (np.zeros((48, 64), dtype=np.int32), TypeError, "uint16"),
    (np.zeros((48, 64, 1), dtype=np.float32), ValueError, "2 dimensions"),
    (np.zeros((64, 96), dtype=np.float32)[:, ::2], ValueError, "C-contiguous"),
    ([[1.0, 2.0]], TypeError, "numpy array"),
    (np.full((48, 64), np.inf, dtype=np.float32), ValueError, "infinite"),
])
def test_bad_depth_arrays(depth, error, message):
    with pytest.raises(error, match=message):
        levelfuse.RangeMap.pinhole(depth, K, np.eye(4))


def nan_pose():
    pose = np.eye(4)
    pose[0, 3] = np.nan
    return pose


def scaled_pose():
    pose = np.eye(4)
    pose[:3, :3] *= 2.0
    return pose


def mirrored_pose():
    pose = np.eye(4)
    pose[0, 0] = -1.0
    return pose


@pytest.mark.parametrize("pose, error, message", [
    (nan_pose(), ValueError, "not finite"),
    (scaled_pose(), ValueError, "not a rigid motion"),
    (mirrored_pose(), ValueError, "mirrors"),
    (np.eye(3), ValueError, "shape \\(4, 4\\)"),
    ("identity", TypeError, "real numbers"),
])
def test_bad_poses(pose, error, message):
    with pytest.raises(error, match=message):
        levelfuse.RangeMap.pinhole(wall(), K, pose)


@pytest.mark.parametrize("k, message", [
    (np.array([[525.0, 1.0, 319.5], [0.0, 525.0, 239.5], [0.0, 0.0, 1.0]]), "no skew"),
    ((-1.0, 525.0, 319.5, 239.5), "positive"),
    ((525.0, 525.0, 319.5), "shape"),
])
def test_bad_intrinsics(k, message):
    with pytest.raises(ValueError, match=message):
        levelfuse.RangeMap.pinhole(wall(), k, np.eye(4))


def test_other_bad_arguments():
    with pytest.raises(ValueError, match="depth_scale"):
        levelfuse.RangeMap.pinhole(np.ones((4, 4), dtype=np.uint16), K, np.eye(4), depth_scale=0.0)
    with pytest.raises(ValueError, match="sigma"):
        levelfuse.RangeMap.pinhole(wall(), K, np.eye(4), sigma=-1.0)
    with pytest.raises(ValueError, match="field of view"):
        levelfuse.RangeMap.pinhole(wall(), (1.0, 1.0, 32.0, 24.0), np.eye(4))
    with pytest.raises(TypeError, match="float32"):
        levelfuse.RangeMap.orthographic(np.zeros((4, 4)), 0.1, np.eye(4), sigma=0.01)


def test_load_scans_reads_what_the_converter_reads(torus_scans):
    maps = levelfuse.load_scans(str(torus_scans))
    assert len(maps) == 6 and all(m.kind == "orthographic" for m in maps)
    frames = levelfuse.load_scans(str(shared("7scenes")), frame_stride=10, max_depth=3.0)
    assert len(frames) == 5 and all(f.kind == "pinhole" for f in frames)


def test_load_scans_reads_an_e57_station():
    (station,) = levelfuse.load_scans(str(shared("e57", "pumpA.e57")))
    assert station.kind == "spherical" and station.name == "pumpA"
    ranges = station.readings()
    assert np.count_nonzero(~np.isnan(ranges)) >= 155201 * 0.99
    assert 1.98 <= np.nanmin(ranges) and np.nanmax(ranges) <= 5.43


def test_bad_files_raise_input_error_naming_them(tmp_path):
    missing = tmp_path / "nothing.conf"
    with pytest.raises(levelfuse.InputError, match="nothing.conf"):
        levelfuse.load_scans(str(missing))
    bad = tmp_path / "scans.json"
    bad.write_text("{ not json")
    with pytest.raises(levelfuse.InputError, match="scans.json") as raised:
        levelfuse.reconstruct(str(bad))
    assert isinstance(raised.value, ValueError)
    png = tmp_path / "depth.png"
    png.write_bytes(b"\x89PNG\r\n\x1a\n truncated")
    with pytest.raises(levelfuse.InputError, match="depth.png"):
        levelfuse.read_depth_png(str(png))
    e57 = tmp_path / "cut.e57"
    e57.write_bytes(b"ASTM-E57" + bytes(1000))
    with pytest.raises(levelfuse.InputError, match="cut.e57: a size of 1008 bytes is not a whole number"):
        levelfuse.load_scans(str(e57))
    with pytest.raises(levelfuse.InputError, match="nothing.vdb"):
        levelfuse.read_vdb(str(tmp_path / "nothing.vdb"))


def test_read_depth_png_gives_the_samples():
    folder = shared("7scenes")
    first = sorted(folder.glob("*.depth.png"))[0]
    samples = levelfuse.read_depth_png(str(first))
    assert samples.dtype == np.uint16 and samples.shape == (480, 640)
    assert 0 < np.count_nonzero(samples) <= samples.size


def test_load_scans_takes_the_converters_options_and_refuses_others(torus_scans):
    with pytest.raises(TypeError, match="'stride'"):
        levelfuse.load_scans(str(torus_scans), stride=2)
    with pytest.raises(levelfuse.InputError, match="frame stride"):
        levelfuse.load_scans(str(shared("7scenes")), frame_stride=0)
    with pytest.raises(TypeError, match="frame_stride must be an integer"):
        levelfuse.load_scans(str(shared("7scenes")), frame_stride=2.5)
