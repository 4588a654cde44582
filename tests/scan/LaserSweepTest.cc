// A spinning LiDAR's sweep listed in firing order: its lasers and their
// cones found, and the sweep binned as one range map per block of lasers.

#include "support/LaserSweeps.h"

#include <levelfuse/scan/LaserSweep.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

constexpr double kDegree = M_PI / 180.0;

TEST(LaserSweep, FindsEachLaserAndItsCone) {
  const test::SweepSensor sensor = test::streetSensor();
  const std::vector<Vec3d> points = test::streetCornerSweep(sensor);
  const std::optional<LaserRows> rows = lasersInFiringOrder(points);
  ASSERT_TRUE(rows);
  ASSERT_EQ(rows->lasers.size(), sensor.lasers.size());
  for (std::size_t l = 0; l < sensor.lasers.size(); ++l) {
    EXPECT_NEAR(rows->lasers[l].apexHeight, sensor.lasers[l].apexHeight, 1e-4) << "laser " << l;
    EXPECT_NEAR(rows->lasers[l].elevation, sensor.lasers[l].elevation, 1e-4 * kDegree) << "laser " << l;
  }
  EXPECT_NEAR(rows->cut, 0.0, sensor.wholeStep);
  EXPECT_NEAR(rows->azimuthStep, sensor.meanStep(), 0.005 * sensor.meanStep());
  // Every return has its laser, those that fired before the cut too.
  ASSERT_EQ(rows->laserOfPoint.size(), points.size());
  std::size_t laser = 0, wrong = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (laser + 1 < sensor.lasers.size() &&
           std::fabs(std::atan2(points[i].z() - sensor.lasers[laser].apexHeight, std::hypot(points[i].x(), points[i].y())) -
                     sensor.lasers[laser].elevation) > 1e-6)
      ++laser;
    wrong += rows->laserOfPoint[i] != static_cast<int>(laser);
  }
  EXPECT_EQ(wrong, 0u);
}

TEST(LaserSweep, ALaserThatSawOneDistanceTakesItsNeighboursApex) {
  // Only the road, which each laser meets at one distance from the axis: no
  // laser's returns tell its apex; each takes the axis's origin, and its cone
  // still runs through its returns.
  const test::SweepSensor sensor = test::streetSensor();
  std::vector<Vec3d> points;
  for (const LaserCone& laser : sensor.lasers) {
    if (laser.elevation > -5.5 * kDegree) continue;  // the road beyond 80 m, or never
    for (double a = 0.0; a < 2.0 * M_PI - 0.5 * sensor.wholeStep; a += sensor.wholeStep) {
      const Vec3d d(std::cos(laser.elevation) * std::cos(a), std::cos(laser.elevation) * std::sin(a),
                    std::sin(laser.elevation));
      points.push_back(Vec3d(0.0, 0.0, laser.apexHeight) + d * ((-1.73 - laser.apexHeight) / d.z()));
    }
  }
  const std::optional<LaserRows> rows = lasersInFiringOrder(points);
  ASSERT_TRUE(rows);
  ASSERT_EQ(rows->lasers.size(), 8u);
  for (std::size_t i = 0; i < points.size(); i += 97) {
    const LaserCone& cone = rows->lasers[static_cast<std::size_t>(rows->laserOfPoint[i])];
    EXPECT_EQ(cone.apexHeight, 0.0);
    EXPECT_NEAR(std::atan2(points[i].z() - cone.apexHeight, std::hypot(points[i].x(), points[i].y())), cone.elevation,
                1e-9);
  }
}

TEST(LaserSweep, KeepsEveryReturnOnItsOwnPixel) {
  const test::SweepSensor sensor = test::streetSensor();
  const std::vector<Vec3d> points = test::streetCornerSweep(sensor);
  const std::optional<LaserRows> rows = lasersInFiringOrder(points);
  ASSERT_TRUE(rows);
  const std::vector<RangeMap> maps = sweepRangeMaps(points, *rows, openvdb::math::Mat4d::identity(), 0.01, "sweep");
  ASSERT_EQ(maps.size(), 2u);  // the two blocks of lasers
  std::size_t readings = 0;
  for (const RangeMap& map : maps) {
    EXPECT_EQ(map.height(), 8);
    readings += map.validCount();
  }
  EXPECT_GE(readings, static_cast<std::size_t>(0.995 * static_cast<double>(points.size())));
  EXPECT_LE(readings, points.size() + 2 * 8);  // a closed turn repeats its first column
  // Each map is seen from its block's mean apex.
  EXPECT_NEAR(maps[0].mapToWorld().getTranslation().z(), 0.126 - 0.0013 * 3.5, 1e-4);
  EXPECT_NEAR(maps[1].mapToWorld().getTranslation().z(), 0.209 - 0.0015 * 3.5, 1e-4);
  EXPECT_EQ(maps[1].name(), "sweep, lasers 1-8");
}

TEST(LaserSweep, ReadingsLieWhereTheReturnsLie) {
  const test::SweepSensor sensor = test::streetSensor();
  const std::vector<Vec3d> points = test::streetCornerSweep(sensor);
  const std::vector<RangeMap> maps =
      sweepRangeMaps(points, *lasersInFiringOrder(points), openvdb::math::Mat4d::identity(), 0.01, "sweep");
  // Each return, where the maps' readings place the surface: its laser's
  // map reads it where it lies (between rows, the readings are interpolated
  // in range, which on a road seen at a grazing angle is not the road).
  std::vector<double> off;
  for (const Vec3d& p : points)
    for (const RangeMap& map : maps) {
      RangeMap::LocalSample s;
      if (map.sampleLocal(map.worldToMap().transform(p), 0.05, s)) off.push_back(std::fabs(s.D));
    }
  ASSERT_GT(off.size(), points.size() / 2);
  std::sort(off.begin(), off.end());
  EXPECT_LT(off[off.size() / 2], 0.5e-3);
  EXPECT_LT(off[static_cast<std::size_t>(0.95 * off.size())], 3e-3);
}

TEST(LaserSweep, FindsNoLasersInAnotherOrder) {
  const test::SweepSensor sensor = test::streetSensor();
  std::vector<Vec3d> points = test::streetCornerSweep(sensor);
  std::vector<Vec3d> shuffled = points;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(5));
  EXPECT_FALSE(lasersInFiringOrder(shuffled));
  // Column after column (every laser at each firing), as a sensor's packets list them.
  std::vector<Vec3d> columns;
  for (int c = 0; c < 1800; ++c)
    for (const LaserCone& laser : sensor.lasers) {
      const double a = c * sensor.wholeStep;
      const Vec3d d(std::cos(laser.elevation) * std::cos(a), std::cos(laser.elevation) * std::sin(a),
                    std::sin(laser.elevation));
      const Vec3d apex(0.0, 0.0, laser.apexHeight);
      const double t = test::streetCornerHit(apex, d);
      if (t > 0.0) columns.push_back(apex + d * t);
    }
  EXPECT_FALSE(lasersInFiringOrder(columns));
  EXPECT_FALSE(lasersInFiringOrder({}));
}

TEST(LaserSweep, RefusesLasersThatDoNotMatchThePoints) {
  const std::vector<Vec3d> points = test::streetCornerSweep(test::streetSensor());
  LaserRows rows = *lasersInFiringOrder(points);
  rows.laserOfPoint.pop_back();
  EXPECT_THROW(sweepRangeMaps(points, rows, openvdb::math::Mat4d::identity(), 0.01, "sweep"), std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse
