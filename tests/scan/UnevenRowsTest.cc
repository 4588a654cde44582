// Spherical range maps whose rows are spaced unevenly, as a spinning LiDAR's
// lasers are (SphericalProjection::rowElevations): the row of an elevation,
// the data term against analytic surfaces, and the binning of a sweep.

#include "support/RangeSampleChecks.h"
#include "support/ScannerPoses.h"

#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/scan/SphericalScan.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;
using Mat4d = openvdb::math::Mat4d;

using test::kDegree;
using test::scannerPose;

/// An HDL-64E's lasers: an upper block of 32 a third of a degree apart from
/// +2 degrees down, and a lower block of 32 half a degree apart below it;
/// lowest first.
std::vector<double> hdl64eElevations() {
  std::vector<double> rows;
  for (int r = 31; r >= 0; --r) rows.push_back((2.0 - 31.0 / 3.0 - 0.5 - 0.5 * r) * kDegree);
  for (int r = 31; r >= 0; --r) rows.push_back((2.0 - r / 3.0) * kDegree);
  return rows;
}

/// Azimuths -60 to 60 degrees in half-degree steps on the HDL-64E's rows.
SphericalProjection unevenGrid() {
  SphericalProjection grid;
  grid.azimuthStart = -60.0 * kDegree;
  grid.azimuthStep = 0.5 * kDegree;
  grid.rowElevations = hdl64eElevations();
  return grid;
}
constexpr int kSweepColumns = 241, kSweepRows = 64;

/// The readings of the grid's rays to the wall x = 4 of the scanner's frame.
std::vector<float> wallRanges(const SphericalProjection& grid) {
  std::vector<float> ranges;
  for (int v = 0; v < kSweepRows; ++v)
    for (int u = 0; u < kSweepColumns; ++u)
      ranges.push_back(static_cast<float>(4.0 / sphericalDirection(grid, u, v).x()));
  return ranges;
}

TEST(UnevenRows, TheRowOfAnElevationIsLinearBetweenRowsAndInvertsElevationOfRow) {
  const SphericalProjection grid = unevenGrid();
  const std::vector<double>& rows = grid.rowElevations;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    EXPECT_NEAR(rowOfElevation(grid, rows[r]), static_cast<double>(r), 1e-9) << r;
    EXPECT_DOUBLE_EQ(elevationOfRow(grid, static_cast<double>(r)), rows[r]) << r;
  }
  for (const double v : {0.25, 10.5, 31.5, 31.9, 32.0, 45.75, 62.999}) {
    EXPECT_NEAR(rowOfElevation(grid, elevationOfRow(grid, v)), v, 1e-9) << v;
    const int below = static_cast<int>(v);
    EXPECT_NEAR(elevationOfRow(grid, v), rows[below] + (v - below) * rowStep(grid, below), 1e-15) << v;
  }
  // Beyond the first and the last row, on the spacing of the nearest two.
  EXPECT_NEAR(rowOfElevation(grid, rows.front() - 0.25 * kDegree), -0.5, 1e-9);
  EXPECT_NEAR(rowOfElevation(grid, rows.back() + kDegree / 6.0), 63.5, 1e-9);
  EXPECT_NEAR(rowStep(grid, 0), 0.5 * kDegree, 1e-12);
  EXPECT_NEAR(rowStep(grid, 40), kDegree / 3.0, 1e-12);
  EXPECT_NEAR(largestRowStep(grid), 0.5 * kDegree, 1e-12);
}

TEST(UnevenRows, TheMapTakesItsElevationStartAndStepFromItsRows) {
  const RangeMap map = RangeMap::spherical(kSweepColumns, kSweepRows,
                                           std::vector<float>(kSweepColumns * kSweepRows, 5.0f), unevenGrid(),
                                           Mat4d::identity(), 0.002, "sphere");
  const SphericalProjection& grid = map.sphericalProjection();
  EXPECT_DOUBLE_EQ(grid.elevationStart, hdl64eElevations().front());
  EXPECT_NEAR(grid.elevationStep, (hdl64eElevations().back() - hdl64eElevations().front()) / 63.0, 1e-15);
  // The largest distance between rays at the readings: the wider of the steps.
  EXPECT_NEAR(map.maxRaySpacing(), 5.0 * 0.5 * kDegree, 1e-6);
}

TEST(UnevenRows, ASphereAroundTheScannerHasTheRayDensityOfItsRows) {
  const Mat4d pose = scannerPose();
  const RangeMap map = RangeMap::spherical(kSweepColumns, kSweepRows,
                                           std::vector<float>(kSweepColumns * kSweepRows, 5.0f), unevenGrid(),
                                           pose, 0.002, "sphere");
  // Below -8.33 degrees the rows are half a degree apart, above it a third.
  for (const auto& [elevation, rowSpacing] : {std::pair<double, double>{-15.0, 0.5}, {-3.0, 1.0 / 3.0}}) {
    const Vec3d local = Vec3d(std::cos(elevation * kDegree), 0.2, std::sin(elevation * kDegree)).unit() * 5.3;
    RangeSample s;
    ASSERT_TRUE(map.sample(pose.transform(local), s)) << elevation;
    EXPECT_NEAR(s.D, 0.3, 1e-6);
    EXPECT_NEAR((s.gradD - pose.transform3x3(local.unit())).length(), 0.0, 1e-6);
    // Rays per unit area across the line of sight: 1 / (r^2 cos(elevation) dtheta dphi), dphi the rows' spacing.
    const double cosElevation = std::hypot(local.x(), local.y()) / local.length();
    EXPECT_NEAR(s.gamma, 1.0 / (local.lengthSqr() * cosElevation * 0.5 * kDegree * rowSpacing * kDegree),
                1e-9 * s.gamma)
        << elevation;
  }
  RangeSample s;
  EXPECT_FALSE(map.sample(pose.transform(Vec3d(5.0, 0.0, 1.0)), s));    // above the highest laser
  EXPECT_FALSE(map.sample(pose.transform(Vec3d(5.0, 0.0, -3.0)), s));   // below the lowest
}

TEST(UnevenRows, AWallGradientIsThatOfItsDistanceOnEitherBlock) {
  const Mat4d pose = scannerPose();
  const SphericalProjection grid = unevenGrid();
  const RangeMap map = RangeMap::spherical(kSweepColumns, kSweepRows, wallRanges(grid), grid, pose, 0.002, "wall");
  // Each reading's point lies on the wall, and projects back to its pixel.
  for (const auto& [u, v] : {std::pair<int, int>{0, 0}, {120, 31}, {120, 32}, {240, 63}, {17, 50}}) {
    const Vec3d local = pose.inverse().transform(map.readingPoint(u, v));
    EXPECT_NEAR(local.x(), 4.0, 1e-5);
    const openvdb::math::Vec2d uv = map.project(local);
    EXPECT_NEAR(uv.x(), u, 1e-6);
    EXPECT_NEAR(uv.y(), v, 1e-6);
  }
  // D's gradient by differences, in the lower block, the upper one and the cell between them
  // (between rows: on a row the bilinear readings have a kink).
  for (const double elevation : {-15.0, -8.5, -2.9}) {
    const Vec3d ray = Vec3d(1.0, 0.3, std::tan(elevation * kDegree) * std::hypot(1.0, 0.3)).unit();
    const Vec3d x = pose.transform(ray * (4.0 / ray.x() - 0.1));
    SCOPED_TRACE(::testing::Message() << "elevation " << elevation);
    RangeSample s;
    ASSERT_TRUE(map.sample(x, s));
    EXPECT_NEAR(s.D, -0.1, 2e-4);
    test::expectGradDByDifferences(map, x, s, 1e-5, 1e-3);
    EXPECT_NEAR(s.gradD.unit().dot(pose.transform3x3(Vec3d(1, 0, 0))), 1.0, 1e-3) << elevation;
  }
}

TEST(UnevenRows, RejectsRowsThatAreNotOnePerRowOrNotIncreasing) {
  const auto make = [](std::vector<double> rows, int height) {
    SphericalProjection grid = unevenGrid();
    grid.rowElevations = std::move(rows);
    return RangeMap::spherical(4, height, std::vector<float>(static_cast<std::size_t>(4 * height), 1.0f), grid,
                               Mat4d::identity(), 0.01, "bad");
  };
  EXPECT_NO_THROW(make({0.0, 0.1, 0.3}, 3));
  EXPECT_THROW(make({0.0, 0.1, 0.3}, 4), std::invalid_argument);          // a row without an elevation
  EXPECT_THROW(make({0.0, 0.1, 0.1}, 3), std::invalid_argument);          // two rows at one elevation
  EXPECT_THROW(make({0.3, 0.1, 0.0}, 3), std::invalid_argument);          // decreasing
  EXPECT_THROW(make({0.0, std::nan(""), 0.3}, 3), std::invalid_argument);  // not finite
  EXPECT_THROW(make({0.0, 0.1, 1.6}, 3), std::invalid_argument);          // past the pole
}

/// An HDL-64E's sweep (a full turn in 2117 steps) of a round room 8 m across
/// with a floor 1.7 m below the sensor: every ray has a return.
std::vector<Vec3d> hdl64eSweepOfARoom() {
  std::vector<Vec3d> points;
  for (const double elevation : hdl64eElevations())
    for (int c = 0; c < 2117; ++c) {
      const double azimuth = -M_PI + (c + 0.5) * 2.0 * M_PI / 2117;
      const Vec3d d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      const double toWall = 4.0 / std::cos(elevation), toFloor = d.z() < 0.0 ? -1.7 / d.z() : 1e9;
      points.push_back(d * std::min(toWall, toFloor));
    }
  return points;
}

TEST(UnevenRows, ASweepOfAnHdl64eGivesEachLaserItsOwnRow) {
  const std::vector<Vec3d> points = hdl64eSweepOfARoom();
  const AngularSteps steps = estimateAngularSteps(points);
  ASSERT_EQ(steps.rowElevations.size(), 64u);
  for (std::size_t r = 0; r < 64; ++r) EXPECT_NEAR(steps.rowElevations[r], hdl64eElevations()[r], 1e-9) << r;
  const RangeMap map = sphericalMapFromPoints(points, steps, Mat4d::identity(), 0.002, "sweep");
  EXPECT_EQ(map.height(), 64);
  EXPECT_EQ(map.width(), 2118);  // a whole turn, closed
  // Every pixel holds its laser's point: no row is empty, none holds two lasers.
  EXPECT_EQ(map.validCount(), static_cast<std::size_t>(map.width()) * 64u);

  // The same sweep on even rows a third of a degree apart leaves a row of
  // pixels empty between every two of the lower block's lasers, and most of
  // its cells without four readings.
  AngularSteps even = steps;
  even.rowElevations.clear();
  const RangeMap evenMap = sphericalMapFromPoints(points, even, Mat4d::identity(), 0.002, "even");
  const double filled = static_cast<double>(evenMap.validCount()) / (static_cast<double>(evenMap.width()) * evenMap.height());
  EXPECT_LT(filled, 0.85);
}

TEST(UnevenRows, EvenRowsAreNoTable) {
  std::vector<Vec3d> points;
  for (int r = 0; r < 32; ++r)
    for (int c = 0; c < 1000; ++c) {
      const double elevation = (-20.0 + 1.25 * r) * kDegree, azimuth = -M_PI + (c + 0.5) * 2.0 * M_PI / 1000;
      points.push_back(Vec3d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                             std::sin(elevation)) * 5.0);
    }
  const AngularSteps steps = estimateAngularSteps(points);
  EXPECT_TRUE(steps.rowElevations.empty());
  EXPECT_NEAR(steps.elevation, 1.25 * kDegree, 1e-9);
}

TEST(UnevenRows, BinningRefusesRowsThatAreNotIncreasing) {
  AngularSteps steps{0.01, 0.01, {0.1, 0.0}};
  const std::vector<Vec3d> points(20, Vec3d(1.0, 0.0, 0.05));
  EXPECT_THROW(sphericalMapFromPoints(points, steps, Mat4d::identity(), 0.002, "bad"), std::invalid_argument);
  steps.rowElevations = {0.1};
  EXPECT_THROW(sphericalMapFromPoints(points, steps, Mat4d::identity(), 0.002, "bad"), std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse
