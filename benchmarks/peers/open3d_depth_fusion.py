#!/usr/bin/python3
"""Open3D's TSDF fusion of a folder of depth frames, run the way its users run it.

    open3d_depth_fusion.py FOLDER OUTPUT.ply [--volume scalable|blocks]
                           [--voxel-size 0.01] [--frame-stride 1]

FOLDER holds frame-NNNNNN.depth.png (16-bit, millimetres) and frame-NNNNNN.pose.txt
(4x4 camera-to-world, metres) with camera-intrinsics.txt (3x3 pinhole), as the
7-Scenes folders in ../shared/data do. Every frame-stride-th frame is fused, as
`levelfuse reconstruct --frame-stride` takes them.

  scalable  the legacy ScalableTSDFVolume (o3d.pipelines.integration), as in
            Open3D's RGBD integration tutorial: integrate each frame, then
            extract_triangle_mesh and write_triangle_mesh
  blocks    the tensor VoxelBlockGrid on the CPU (o3d.t.geometry), as in
            Open3D's voxel block grid tutorial: blocks of 16 voxels, each frame's
            blocks found with compute_unique_block_coordinates, then integrate,
            extract_triangle_mesh and write, both with the tutorial's truncation,
            Open3D's default of 8 voxels (with 4, extraction fails an assertion of
            Debian's build on the 500 frames of 7scenes-seq, and on 50 now and then).
            Room for 10,000 blocks at first: the block table grows as it fills,
            and the tutorial's 50,000 would reserve 1.6 GB before the first frame

Both use what the tutorials use: sdf_trunc 4 voxels (blocks: 8), depth_scale 1000,
depth_trunc / depth_max 4 m, no colour, Open3D's own threading and environment.
Nothing else is set. With --phases, the time of reading and integrating the
frames, of extracting the mesh and of writing it go to standard error.
Exits 2 with a message on a missing or unreadable input.
"""

import argparse
import glob
import os
import sys
import time

import numpy as np
import open3d as o3d

TRUNCATION_VOXELS = 4.0
DEPTH_SCALE = 1000.0  # PNG units per metre
DEPTH_MAX = 4.0       # metres


def fail(message):
    print(f"open3d_depth_fusion: {message}", file=sys.stderr)
    sys.exit(2)


def matrix_of(path, size, what):
    """The size x size matrix in a text file, or a message naming the file."""
    try:
        m = np.loadtxt(path)
    except (OSError, ValueError) as error:
        fail(f"{path}: not a readable {what} ({error})")
    if m.shape != (size, size):
        fail(f"{path}: a {what} has {size}x{size} numbers, this has {m.size}")
    return m


def frames_of(folder, stride):
    """The folder's (depth PNG, camera-to-world pose) pairs, sorted, every stride-th."""
    depths = sorted(glob.glob(os.path.join(folder, "frame-*.depth.png")))
    if not depths:
        fail(f"{folder}: no frame-*.depth.png files")
    return [(depth, matrix_of(depth[: -len(".depth.png")] + ".pose.txt", 4, "camera-to-world pose"))
            for depth in depths[::stride]]


def intrinsics_of(folder):
    return matrix_of(os.path.join(folder, "camera-intrinsics.txt"), 3, "pinhole intrinsic matrix")


def read_depth(path, reader):
    image = reader(path)
    if image.is_empty():
        fail(f"{path}: not a depth PNG Open3D can read")
    return image


def report_phases(started, frames, extracting):
    """Integration (reading included) and extraction times, on standard error."""
    integrated = extracting - started
    print(f"integrating {integrated:.2f} s ({1000 * integrated / len(frames):.1f} ms a frame), "
          f"extracting {time.monotonic() - extracting:.2f} s", file=sys.stderr)


def fuse_scalable(frames, k, voxel, started=None):
    """The legacy ScalableTSDFVolume, as Open3D's RGBD integration tutorial runs it."""
    volume = o3d.pipelines.integration.ScalableTSDFVolume(
        voxel_length=voxel, sdf_trunc=TRUNCATION_VOXELS * voxel,
        color_type=o3d.pipelines.integration.TSDFVolumeColorType.NoColor)
    first = read_depth(frames[0][0], o3d.io.read_image)
    height, width = np.asarray(first).shape[:2]
    intrinsic = o3d.camera.PinholeCameraIntrinsic(width, height, k[0, 0], k[1, 1], k[0, 2], k[1, 2])
    blank = o3d.geometry.Image(np.zeros((height, width), dtype=np.uint8))  # no colour
    for depth_path, pose in frames:
        depth = read_depth(depth_path, o3d.io.read_image)
        rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
            blank, depth, depth_scale=DEPTH_SCALE, depth_trunc=DEPTH_MAX, convert_rgb_to_intensity=True)
        volume.integrate(rgbd, intrinsic, np.linalg.inv(pose))
    extracting = time.monotonic()
    mesh = volume.extract_triangle_mesh()
    if started:
        report_phases(started, frames, extracting)
    return mesh


def fuse_blocks(frames, k, voxel, started=None):
    """The tensor VoxelBlockGrid on the CPU, as Open3D's voxel block grid tutorial runs it."""
    device = o3d.core.Device("CPU:0")
    grid = o3d.t.geometry.VoxelBlockGrid(
        attr_names=("tsdf", "weight"), attr_dtypes=(o3d.core.float32, o3d.core.float32),
        attr_channels=((1), (1)), voxel_size=voxel, block_resolution=16, block_count=10000, device=device)
    intrinsic = o3d.core.Tensor(k, o3d.core.Dtype.Float64)
    for depth_path, pose in frames:
        depth = read_depth(depth_path, o3d.t.io.read_image).to(device)
        extrinsic = o3d.core.Tensor(np.linalg.inv(pose), o3d.core.Dtype.Float64)
        blocks = grid.compute_unique_block_coordinates(
            depth, intrinsic, extrinsic, DEPTH_SCALE, DEPTH_MAX)
        grid.integrate(blocks, depth, intrinsic, extrinsic, DEPTH_SCALE, DEPTH_MAX)
    extracting = time.monotonic()
    mesh = grid.extract_triangle_mesh().to_legacy()
    if started:
        report_phases(started, frames, extracting)
    return mesh


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folder")
    parser.add_argument("output", help="the mesh (.ply)")
    parser.add_argument("--volume", choices=("scalable", "blocks"), default="scalable")
    parser.add_argument("--voxel-size", type=float, default=0.01, help="metres")
    parser.add_argument("--frame-stride", type=int, default=1)
    parser.add_argument("--phases", action="store_true", help="print each phase's time to standard error")
    args = parser.parse_args()
    if args.voxel_size <= 0 or args.frame_stride < 1:
        fail("the voxel size must be positive and the frame stride at least 1")
    frames = frames_of(args.folder, args.frame_stride)
    k = intrinsics_of(args.folder)
    fuse = fuse_scalable if args.volume == "scalable" else fuse_blocks
    started = time.monotonic()
    mesh = fuse(frames, k, args.voxel_size, started if args.phases else None)
    written = time.monotonic()
    if not o3d.io.write_triangle_mesh(args.output, mesh):
        fail(f"{args.output}: could not be written")
    if args.phases:
        print(f"writing {time.monotonic() - written:.2f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
