# levelfuse.Fusion: depth frames integrated one at a time, as Open3D and vdbfusion users work.
import numpy as np
import pytest

import levelfuse
from conftest import shared


def frames_of(folder, stride):
    images = sorted(folder.glob("*.depth.png"))[::stride]
    K = np.loadtxt(folder / "camera-intrinsics.txt")
    for image in images:
        pose = np.loadtxt(str(image).replace(".depth.png", ".pose.txt"))
        yield image, levelfuse.read_depth_png(str(image)), K, pose


def test_frame_by_frame_integration_equals_loading_the_folder():
    folder = shared("7scenes")
    batch = levelfuse.reconstruct(str(folder), frame_stride=5, voxel_size=0.04, data_term="grids")
    fusion = levelfuse.Fusion(voxel_size=0.04, epsilon=batch.summary["epsilon"])
    for image, depth, K, pose in frames_of(folder, 5):
        fusion.integrate(depth, K, pose, name=image.name)
    assert fusion.scan_count == batch.summary["scans"] == 10
    assert fusion.memory_bytes > 0
    frame_by_frame = fusion.reconstruct()
    a, b = batch.grid.active_voxels(), frame_by_frame.grid.active_voxels()
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    w, v = batch.weight_grid.active_voxels(), frame_by_frame.weight_grid.active_voxels()
    assert np.array_equal(w[1], v[1])
    assert frame_by_frame.summary["scene"] is True


def test_reconstructions_can_be_asked_for_while_frames_keep_coming():
    folder = shared("7scenes")
    fusion = levelfuse.Fusion(voxel_size=0.05)
    counts = []
    for i, (image, depth, K, pose) in enumerate(frames_of(folder, 10)):
        fusion.integrate(levelfuse.RangeMap.pinhole(depth, K, pose, name=image.name))
        if i in (1, 4):
            result = fusion.linear_solution(fit=False)
            counts.append(result.summary["scans"])
            assert result.summary["method"] == "linear"
    assert counts == [2, 5]
    picture = fusion.reconstruct(fit=False).preview(width=80)
    assert picture.shape == (60, 80, 3)  # seen from the first frame's camera, with its aspect


def test_a_fusion_refuses_bad_settings_and_frames():
    with pytest.raises(ValueError, match="voxel_size"):
        levelfuse.Fusion(voxel_size=0.0)
    with pytest.raises(ValueError, match="levels"):
        levelfuse.Fusion(voxel_size=0.01, levels=20)
    fusion = levelfuse.Fusion(voxel_size=0.01)
    with pytest.raises(ValueError, match="no range maps"):
        fusion.linear_solution()
    with pytest.raises(TypeError, match="float32"):
        fusion.integrate(np.zeros((4, 4)), np.eye(3), np.eye(4))
    with pytest.raises(ValueError, match="field of view"):
        fusion.integrate(np.ones((4, 4), dtype=np.float32), (0.1, 0.1, 2.0, 2.0), np.eye(4))
    fusion.integrate(np.full((48, 64), 2.0, dtype=np.float32), (52.5, 52.5, 31.5, 23.5), np.eye(4))
    with pytest.raises(ValueError, match="voxel"):
        fusion.reconstruct(voxel_size=0.02)
