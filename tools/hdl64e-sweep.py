#!/usr/bin/env python3
"""Writes one sweep of a Velodyne HDL-64E-like spinning LiDAR as an XYZ point file.

    tools/hdl64e-sweep.py sweep.xyz

The sensor stands at the origin, z up, in a round room 8 m across whose floor
lies 1.7 m below it, with a box 1 m wide and 1 m high on the floor 1.5 m
ahead. Its 64 lasers are spaced as the HDL-64E's: an upper block of 32 a third
of a degree apart from +2 degrees down, and a lower block of 32 half a degree
apart below it, to -24.33 degrees. A turn has 2117 columns. Every ray returns;
the points carry no noise. docs/RESULTS.md ("A spinning LiDAR's uneven rows")
reconstructs it.
"""
import math
import sys

ROOM_RADIUS, FLOOR, COLUMNS = 4.0, -1.7, 2117
BOX = [(1.5, 2.5), (-0.5, 0.5), (-1.7, -0.7)]  # x, y, z extents (m)


def laser_elevations():
    """Degrees, lowest first."""
    lower = [2.0 - 31.0 / 3.0 - 0.5 - 0.5 * r for r in range(31, -1, -1)]
    upper = [2.0 - r / 3.0 for r in range(31, -1, -1)]
    return lower + upper


def box_hit(d):
    """The distance along unit direction d to the box, or None."""
    near, far = 0.0, math.inf
    for k, (lo, hi) in enumerate(BOX):
        if abs(d[k]) < 1e-12:
            if not lo <= 0.0 <= hi:
                return None
            continue
        t1, t2 = sorted((lo / d[k], hi / d[k]))
        near, far = max(near, t1), min(far, t2)
    return near if 0.0 < near <= far else None


def main(path):
    with open(path, "w") as out:
        for elevation in map(math.radians, laser_elevations()):
            for c in range(COLUMNS):
                azimuth = -math.pi + (c + 0.5) * 2.0 * math.pi / COLUMNS
                d = (math.cos(elevation) * math.cos(azimuth), math.cos(elevation) * math.sin(azimuth),
                     math.sin(elevation))
                t = ROOM_RADIUS / math.cos(elevation)
                if d[2] < 0.0:
                    t = min(t, FLOOR / d[2])
                hit = box_hit(d)
                if hit is not None:
                    t = min(t, hit)
                out.write("%.6f %.6f %.6f\n" % (d[0] * t, d[1] * t, d[2] * t))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: hdl64e-sweep.py OUTPUT.xyz")
    main(sys.argv[1])
