"""Depth video fused frame by frame with levelfuse, the way Open3D and vdbfusion users work.

    python3 examples/fuse_depth_frames.py [FOLDER] [OUT_DIR]

FOLDER holds 7-Scenes frames (frame-*.depth.png, frame-*.pose.txt, camera-intrinsics.txt);
by default the 50 frames in ../shared/data/7scenes. Writes room-so-far.png every 10 frames as
they come, then room.vdb, room.ply and room.png.
"""
import pathlib
import sys
import time

import numpy as np

import levelfuse

here = pathlib.Path(__file__).resolve().parent
folder = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else here.parent.parent / "shared" / "data" / "7scenes"
out = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else pathlib.Path("out")
out.mkdir(parents=True, exist_ok=True)

# %% The camera: a 3x3 intrinsic matrix; each frame: 16-bit depth in millimetres and a 4x4
# camera-to-world pose (column vectors), as any numpy code holds them.
# Every REFRESH frames the view of the surface so far is drawn again, as a scanning app does: each
# answer asks only the new frames about what the last one carved (the fusion keeps those votes).
REFRESH = 10
K = np.loadtxt(folder / "camera-intrinsics.txt")
fusion = levelfuse.Fusion(voxel_size=0.01)  # 1 cm voxels
started = time.monotonic()
for image in sorted(folder.glob("*.depth.png")):
    depth = levelfuse.read_depth_png(str(image))  # (480, 640) uint16
    pose = np.loadtxt(str(image).replace(".depth.png", ".pose.txt"))
    fusion.integrate(depth, K, pose, depth_scale=0.001, name=image.name)
    if fusion.scan_count % REFRESH == 0:
        asked = time.monotonic()
        fusion.linear_solution(fit=False).write_preview(str(out / "room-so-far.png"))
        print(f"  {fusion.scan_count} frames: the view of the surface so far redrawn in "
              f"{time.monotonic() - asked:.2f} s")
print(f"{fusion.scan_count} frames integrated in {time.monotonic() - started:.1f} s, "
      f"{fusion.memory_bytes / 2**20:.0f} MiB held")

# %% The surface from the frames so far; it can be asked for again as more frames come.
def report(progress):
    if progress["stage"] == "evolving":
        print(f"\r  iteration {progress['iteration']}, {progress['active_set_voxels']} active voxels", end="")


result = fusion.reconstruct(progress=report)
summary = result.summary
print(f"\n{summary['scans']} frames -> {summary['narrow_band_voxels']} narrow-band voxels in "
      f"{summary['seconds']:.1f} s; the frames' points lie {summary['fit']['mean'] * 1000:.1f} mm from it on average")

# %% The results: a level set for OpenVDB (pyopenvdb, Houdini), a mesh as numpy arrays, a picture.
mesh = result.mesh()  # what no frame saw is left out of a scene's mesh
print(f"mesh: {mesh.vertices.shape[0]} vertices, {mesh.triangles.shape[0]} triangles")
result.write_vdb(str(out / "room.vdb"))
mesh.write(str(out / "room.ply"))
result.write_preview(str(out / "room.png"))  # seen from the first frame's camera
try:
    import pyopenvdb

    grid = result.level_set  # a pyopenvdb.FloatGrid sharing levelfuse's grid, no copy
    print(f"pyopenvdb: {grid.name}, {grid.activeVoxelCount()} active voxels, box {grid.evalActiveVoxelBoundingBox()}")
except ImportError:
    coords, values = result.grid.active_voxels()  # numpy, without pyopenvdb
    print(f"{len(values)} active voxels")
print(f"wrote {out / 'room.vdb'}, {out / 'room.ply'} and {out / 'room.png'}")
