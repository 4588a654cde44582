#!/usr/bin/python3
"""Depth video, levelfuse against Open3D, as whole processes run the way their users run them.

    depth_video_processes.py --build BUILD [--data FOLDER] [--runs 3] [--out DIR]
                             [--case VOXEL_MM:FRAME_STRIDE ...] [--json FILE]

Each case fuses the depth video in FOLDER (default ../shared/data/7scenes-seq) at a
voxel size with every FRAME_STRIDE-th frame, three ways, each as its own process
under /usr/bin/time (wall time, user + system CPU time, peak resident memory):

  levelfuse  levelfuse reconstruct FOLDER --voxel-size V [--frame-stride S] -q
             -o room.vdb --mesh room.ply   (the converter with its defaults)
  scalable   Open3D's ScalableTSDFVolume from Python    (peers/open3d_depth_fusion.py)
  blocks     Open3D's tensor VoxelBlockGrid on the CPU  (peers/open3d_depth_fusion.py)

The three run in turn (A B C A B C ...), RUNS times, in the environment this
script was given: nothing is set for or against any of them. The medians are
printed as a Markdown table with levelfuse's ratios to each peer, and each
mesh's distance from the held-out frames (positions 5, 15, ..., those a run with
frame stride 10 never sees) by heldout_ruler. With frame stride 1 the
"held-out" frames are among those fused: the numbers then say how well the
mesh fits frames it was made from.

Default cases: 10 mm from all 500 frames, and 5 mm from every 10th frame.
"""

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PEER = os.path.join(HERE, "peers", "open3d_depth_fusion.py")


def command_for(tool, build, data, voxel, stride, out):
    mesh = os.path.join(out, f"{tool}.ply")
    if tool == "levelfuse":
        command = [os.path.join(build, "tools", "levelfuse", "levelfuse"), "reconstruct", data,
                   "--voxel-size", str(voxel), "-q", "-o", os.path.join(out, "room.vdb"), "--mesh", mesh]
        if stride > 1:
            command += ["--frame-stride", str(stride)]
        return command, mesh
    return [sys.executable, PEER, data, mesh, "--volume", tool, "--voxel-size", str(voxel),
            "--frame-stride", str(stride)], mesh


ATTEMPTS = 3  # Open3D 0.16's VoxelBlockGrid extraction now and then fails an assertion of its own


def timed(command):
    """Wall s, CPU s (user + system) and peak resident MiB of one process, by
    /usr/bin/time, and how many attempts before it failed (run again, as its
    user would, up to ATTEMPTS times)."""
    for failed in range(ATTEMPTS):
        with tempfile.NamedTemporaryFile("r", suffix=".time") as record:
            result = subprocess.run(["/usr/bin/time", "-f", "%e %U %S %M", "-o", record.name] + command,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if result.returncode == 0:
                wall, user, system, kib = record.read().split()[-4:]
                return {"wall_s": float(wall), "cpu_s": float(user) + float(system),
                        "peak_mib": float(kib) / 1024.0, "failed_before": failed}
        print(f"depth_video_processes: {' '.join(command)} failed:\n{result.stderr}", file=sys.stderr)
    sys.exit(f"depth_video_processes: {' '.join(command)} failed {ATTEMPTS} times")


def held_out(build, mesh, data):
    ruler = os.path.join(build, "benchmarks", "heldout_ruler")
    result = subprocess.run([ruler, mesh, data], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"depth_video_processes: heldout_ruler {mesh}: {result.stderr}")
    return json.loads(result.stdout)


def run_case(args, voxel_mm, stride, tools):
    out = os.path.join(args.out, f"{voxel_mm}mm-stride{stride}")
    os.makedirs(out, exist_ok=True)
    runs = {tool: [] for tool in tools}
    meshes = {}
    for run in range(args.runs):
        for tool in tools:
            command, meshes[tool] = command_for(tool, args.build, args.data, voxel_mm / 1000.0, stride, out)
            runs[tool].append(timed(command))
            print(f"  {voxel_mm} mm, stride {stride}, run {run + 1}: {tool} {runs[tool][-1]}", file=sys.stderr)
    medians = {tool: {key: statistics.median(r[key] for r in runs[tool]) for key in ("wall_s", "cpu_s", "peak_mib")}
               for tool in tools}
    for tool in tools:
        medians[tool]["failed_runs"] = sum(r["failed_before"] for r in runs[tool])
    accuracy = {tool: held_out(args.build, meshes[tool], args.data) for tool in tools}
    return {"voxel_mm": voxel_mm, "frame_stride": stride, "runs": runs, "medians": medians,
            "held_out": accuracy}


def print_table(case, tools):
    medians, accuracy = case["medians"], case["held_out"]
    seen = "held-out" if case["frame_stride"] > 1 else "seen (fused)"
    print(f"\n{case['voxel_mm']} mm, every {case['frame_stride']} frame(s), medians of "
          f"{len(case['runs'][tools[0]])} runs; distances from the {seen} frames:\n")
    print("| | wall | CPU | peak memory | mean | median | within 1 cm |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for tool in tools:
        m, a = medians[tool], accuracy[tool]
        failures = f" ({m['failed_runs']} failed runs repeated)" if m["failed_runs"] else ""
        print(f"| {tool}{failures} | {m['wall_s']:.1f} s | {m['cpu_s']:.1f} s | {m['peak_mib']:.0f} MiB | "
              f"{a['mean_mm']:.2f} mm | {a['median_mm']:.2f} mm | {100 * a['within_1cm']:.1f}% |")
    lf = medians["levelfuse"]
    for peer in tools[1:]:
        p = medians[peer]
        print(f"\nlevelfuse / {peer}: wall {lf['wall_s'] / p['wall_s']:.2f}x, CPU {lf['cpu_s'] / p['cpu_s']:.2f}x, "
              f"memory {lf['peak_mib'] / p['peak_mib']:.2f}x")


def machine():
    model = platform.machine()
    try:
        with open("/proc/cpuinfo") as cpuinfo:
            model = next(line.split(":", 1)[1].strip() for line in cpuinfo if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{time.strftime('%Y-%m-%d')}, {os.cpu_count()} cores, {model}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", required=True, help="levelfuse's build folder")
    parser.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data", "7scenes-seq"))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "depth-video"))
    parser.add_argument("--case", action="append", help="VOXEL_MM:FRAME_STRIDE (default 10:1 and 5:10)")
    parser.add_argument("--peers", default="scalable,blocks", help="comma-separated: scalable, blocks")
    parser.add_argument("--json", help="also write every run and median here")
    args = parser.parse_args()
    cases = [tuple(int(v) for v in c.split(":")) for c in (args.case or ["10:1", "5:10"])]
    tools = ["levelfuse"] + [p for p in args.peers.split(",") if p]
    print(machine())
    results = []
    for voxel_mm, stride in cases:
        results.append(run_case(args, voxel_mm, stride, tools))
        print_table(results[-1], tools)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
