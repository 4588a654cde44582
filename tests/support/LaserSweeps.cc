// A spinning LiDAR's sweep of a street corner, in firing order.

#include "LaserSweeps.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

namespace levelfuse::test {

using openvdb::Vec3d;

namespace {

constexpr double kDegree = M_PI / 180.0;

}  // namespace

SweepSensor streetSensor() {
  SweepSensor sensor;
  for (int i = 0; i < 8; ++i) sensor.lasers.push_back({0.209 - 0.0015 * i, (2.0 - i) * kDegree});
  for (int i = 0; i < 8; ++i) sensor.lasers.push_back({0.126 - 0.0013 * i, (-8.0 - 0.5 * i) * kDegree});
  sensor.wholeStep = 0.2 * kDegree;
  return sensor;
}

double streetCornerHit(const Vec3d& from, const Vec3d& d) {
  double nearest = -1.0;
  const auto consider = [&](double t, bool within) {
    if (t > 0.0 && t < 80.0 && within && (nearest < 0.0 || t < nearest)) nearest = t;
  };
  if (d.z() < 0.0) consider((-1.73 - from.z()) / d.z(), true);
  if (d.x() > 0.0) {
    const double t = (8.0 - from.x()) / d.x();
    const Vec3d p = from + d * t;
    consider(t, std::fabs(p.y()) <= 3.0 && p.z() >= -1.73 && p.z() <= 2.27);
  }
  // A parked car: a box's slabs.
  const Vec3d low(3.0, 2.0, -1.73), high(5.0, 4.5, -0.3);
  double enter = 0.0, leave = 80.0;
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0.0) {
      if (from[axis] < low[axis] || from[axis] > high[axis]) enter = leave + 1.0;
      continue;
    }
    double t0 = (low[axis] - from[axis]) / d[axis], t1 = (high[axis] - from[axis]) / d[axis];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  }
  consider(enter, enter <= leave);
  if (d.x() < 0.0) {
    const double t = (-20.0 - from.x()) / d.x();
    const Vec3d p = from + d * t;
    consider(t, std::fabs(p.y()) <= 30.0 && p.z() >= -1.73 && p.z() <= 10.0);
  }
  return nearest;
}

std::vector<Vec3d> streetCornerSweep(const SweepSensor& sensor, unsigned seed, const Vec3d& at) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> startOffset(-0.6, 1.2);  // in whole steps
  std::uniform_int_distribution<int> missing(0, 31);
  std::vector<Vec3d> points;
  for (const LaserCone& laser : sensor.lasers) {
    const Vec3d apex = at + Vec3d(0.0, 0.0, laser.apexHeight);
    double azimuth = startOffset(random) * sensor.wholeStep;
    for (int firing = 0; azimuth < 2.0 * M_PI - 0.6 * sensor.wholeStep; ++firing) {
      const Vec3d d(std::cos(laser.elevation) * std::cos(azimuth), std::cos(laser.elevation) * std::sin(azimuth),
                    std::sin(laser.elevation));
      const double t = streetCornerHit(apex, d);
      if (t > 0.0 && missing(random) != 0) points.push_back(apex + d * t - at);
      azimuth += (firing % 7 == 6 ? 0.5 : 1.0) * sensor.wholeStep;
    }
  }
  return points;
}

}  // namespace levelfuse::test
