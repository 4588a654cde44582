// A spinning LiDAR's sweep of a street corner, listed laser by laser in
// firing order as KITTI lists its sweeps: two blocks of lasers whose cones'
// apexes sit 20 and 12 cm up the sensor's axis, a firing pattern of six
// whole steps and a half one (the HDL-64E's), lasers that begin their turn a
// little before or after the cut, and returns missing at random.
#pragma once

#include <levelfuse/scan/LaserSweep.h>

#include <openvdb/math/Vec3.h>

#include <vector>

namespace levelfuse::test {

/// The sensor: its lasers' cones in firing order, and its firing step.
struct SweepSensor {
  std::vector<LaserCone> lasers;
  double wholeStep = 0.0;  ///< radians; every seventh step is half of it
  double meanStep() const { return (6.0 + 0.5) / 7.0 * wholeStep; }
};

/// Eight lasers a degree apart from 2 degrees up to 5 down, apexes near
/// 20 cm, then eight half a degree apart from 8 to 11.5 degrees down, apexes
/// near 12 cm; a whole step of 0.2 degrees.
SweepSensor streetSensor();

/// The scene's surface along a ray from `from` in direction `d`: a road
/// 1.73 m below the sensor's origin, a wall at x = 8 m, 6 m wide and 4 m
/// tall, a car parked beside it (a box 2 x 2.5 x 1.43 m) and a building's
/// face at x = -20 m, 60 m wide and 11.73 m tall; the
/// distance along the ray, or a negative number for none within 80 m.
double streetCornerHit(const openvdb::Vec3d& from, const openvdb::Vec3d& d);

/// The sweep's returns of the sensor standing at `at` (its axes the
/// scene's), in the sensor's frame, laser after laser from the cut at
/// azimuth 0, each laser's first firing up to 0.6 of a step before the cut
/// or 1.2 after it; one return in 32 (at random, seeded) is missing.
std::vector<openvdb::Vec3d> streetCornerSweep(const SweepSensor& sensor, unsigned seed = 7,
                                              const openvdb::Vec3d& at = openvdb::Vec3d(0.0));

}  // namespace levelfuse::test
