// Spherical range maps (terrestrial laser scanners, spinning LiDAR) against
// analytic spheres and planes, and the binning of a scanner's points.

#include "support/RangeSampleChecks.h"
#include "support/ScannerPoses.h"

#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/scan/SphericalScan.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;
using Mat4d = openvdb::math::Mat4d;

using test::kDegree;
using test::scannerPose;

/// Azimuths -60 to 60 degrees and elevations -30 to 40 in half-degree steps.
SphericalProjection halfDegreeGrid() { return {-60.0 * kDegree, 0.5 * kDegree, -30.0 * kDegree, 0.5 * kDegree}; }
constexpr int kColumns = 241, kRows = 141;

/// The ranges of the grid's rays to the surface whose range along a unit
/// direction (scanner frame) `rangeOf` gives.
template <typename RangeOf>
std::vector<float> rangesOf(const SphericalProjection& grid, int columns, int rows, const RangeOf& rangeOf) {
  std::vector<float> ranges;
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < columns; ++u) ranges.push_back(static_cast<float>(rangeOf(sphericalDirection(grid, u, v))));
  return ranges;
}

/// The wall x = 4 of the scanner's frame.
RangeMap wall(const Mat4d& pose) {
  const auto range = [](const Vec3d& d) { return 4.0 / d.x(); };
  return RangeMap::spherical(kColumns, kRows, rangesOf(halfDegreeGrid(), kColumns, kRows, range), halfDegreeGrid(),
                             pose, 0.002, "wall");
}

TEST(SphericalRangeMap, ASphereAroundTheScanner) {
  // Every range 5: D is the distance from the sphere, grad D the line of sight.
  const Mat4d pose = scannerPose();
  const RangeMap map =
      RangeMap::spherical(kColumns, kRows, std::vector<float>(kColumns * kRows, 5.0f), halfDegreeGrid(), pose, 0.002);
  EXPECT_EQ(map.kind(), RangeMap::Kind::kSpherical);
  EXPECT_TRUE(map.raysFromOneCentre());
  EXPECT_STREQ(projectionName(map.kind()), "spherical");
  EXPECT_NEAR((map.scannerPosition() - Vec3d(1.0, 2.0, 3.0)).length(), 0.0, 1e-12);
  for (const Vec3d& local : {Vec3d(5.1, 0.3, 0.4), Vec3d(3.0, -2.0, 1.5), Vec3d(4.0, 1.0, -2.0)}) {
    RangeSample s;
    ASSERT_TRUE(map.sample(pose.transform(local), s)) << local;
    EXPECT_NEAR(s.D, local.length() - 5.0, 1e-6);
    EXPECT_NEAR((s.gradD - pose.transform3x3(local.unit())).length(), 0.0, 1e-6);
    EXPECT_NEAR((s.lineOfSight - pose.transform3x3(local.unit())).length(), 0.0, 1e-12);
    // Rays per unit area across the line of sight: 1 / (r^2 cos(elevation) dtheta dphi), Eq. 13's Jacobian.
    const double cosElevation = std::hypot(local.x(), local.y()) / local.length();
    EXPECT_NEAR(s.gamma, 1.0 / (local.lengthSqr() * cosElevation * std::pow(0.5 * kDegree, 2)), 1e-9 * s.gamma);
    EXPECT_DOUBLE_EQ(s.sigma, 0.002);
  }
  RangeSample s;
  EXPECT_FALSE(map.sample(pose.transform(Vec3d(-5.0, 0.0, 0.0)), s));  // behind the sweep's azimuths
  EXPECT_FALSE(map.sample(pose.transform(Vec3d(1.0, 0.0, 5.0)), s));   // above its elevations
  EXPECT_FALSE(map.sample(pose.transform(Vec3d(0.0, 0.0, 0.0)), s));   // at the scanner
}

TEST(SphericalRangeMap, AStationsSurfacesReachHalfAPixelBeyondTheirLastRays) {
  // A board 2 m away (x = 2) before the wall x = 4, the board's edge between
  // columns 119 and 120 (azimuth -0.5 and 0 degrees); a lone return at 3 m
  // among rays without one, above the wall.
  const SphericalProjection grid = halfDegreeGrid();
  std::vector<float> ranges = rangesOf(grid, kColumns, kRows, [](const Vec3d& d) {
    return (std::atan2(d.y(), d.x()) < -0.25 * kDegree ? 2.0 : 4.0) / d.x();
  });
  const auto at = [](int u, int v) { return static_cast<std::size_t>(v) * kColumns + static_cast<std::size_t>(u); };
  for (int v = 130; v < kRows; ++v)
    for (int u = 0; u < kColumns; ++u) ranges[at(u, v)] = std::numeric_limits<float>::quiet_NaN();
  ranges[at(60, 135)] = 3.0f;
  const RangeMap map = RangeMap::spherical(kColumns, kRows, ranges, grid, Mat4d::identity(), 0.002, "board");
  const auto onRay = [&](double u, double v, double range) {
    const double azimuth = grid.azimuthStart + u * grid.azimuthStep;
    const double elevation = grid.elevationStart + v * grid.elevationStep;
    return Vec3d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                 std::sin(elevation)) * range;
  };
  const auto onBoard = [&](double u, double v) {
    const Vec3d d = onRay(u, v, 1.0);
    return d * (2.0 / d.x());
  };
  RangeSample s;
  // A third of a pixel beyond the board's last column: still on the board.
  ASSERT_TRUE(map.sample(onBoard(119.3, 40.2), s));
  EXPECT_NEAR(s.D, 0.0, 1e-4);
  EXPECT_NEAR(s.gradD.dot(Vec3d(1.0, 0.0, 0.0)) / s.gradD.length(), 1.0, 1e-3);  // the board faces the scanner
  // And the wall a third of a pixel before its first column there.
  const Vec3d wallDirection = onRay(119.7, 40.2, 1.0);
  ASSERT_TRUE(map.sample(wallDirection * (4.0 / wallDirection.x()), s));
  EXPECT_NEAR(s.D, 0.0, 1e-4);
  // Not half a pixel beyond: there the wall's reading speaks.
  ASSERT_TRUE(map.sample(onBoard(119.6, 40.2), s));
  EXPECT_LT(s.D, -1.0);
  // A lone return is a corner of no usable cell: nothing to extend.
  EXPECT_FALSE(map.sample(onRay(60.1, 135.1, 3.0), s));
  // Nor does the wall reach into the rays without a return above it.
  EXPECT_FALSE(map.sample(onRay(80.0, 130.6, 4.0 / std::cos(20.0 * kDegree)), s));
}

TEST(SphericalRangeMap, AStationsSurfacesReachHalfAPixelBeyondItsBorder) {
  // The wall x = 4 seen over the whole grid: its outermost rays stand for the
  // half pixel beyond them too, where the wall's readings are extrapolated.
  const RangeMap map = wall(Mat4d::identity());
  const SphericalProjection grid = halfDegreeGrid();
  const auto onWall = [&](double u, double v) {
    const Vec3d d = sphericalDirection(grid, u, v);
    return d * (4.0 / d.x());
  };
  EXPECT_EQ(map.borderReach(), 0.5);
  for (const auto& [u, v] : {std::pair{-0.3, 70.0}, std::pair{kColumns - 0.7, 70.0}, std::pair{120.0, -0.45},
                             std::pair{120.0, kRows - 0.6}, std::pair{-0.4, -0.4}}) {
    RangeSample s;
    ASSERT_TRUE(map.sample(onWall(u, v), s)) << u << ", " << v;
    EXPECT_NEAR(s.D, 0.0, 2e-3) << u << ", " << v;  // the range extrapolated linearly, the wall 60 degrees off
    EXPECT_GT(s.gradD.dot(Vec3d(1.0, 0.0, 0.0)) / s.gradD.length(), 0.999) << u << ", " << v;
  }
  // No farther.
  for (const auto& [u, v] : {std::pair{-0.55, 70.0}, std::pair{120.0, kRows - 0.45}}) {
    RangeSample s;
    EXPECT_FALSE(map.sample(onWall(u, v), s)) << u << ", " << v;
  }
}

TEST(SphericalRangeMap, AWallGradientIsThatOfItsDistance) {
  const Mat4d pose = scannerPose();
  const RangeMap map = wall(pose);
  EXPECT_EQ(map.validCount(), static_cast<std::size_t>(kColumns * kRows));
  // Each reading's point lies on the wall, and projects back to its pixel.
  for (const auto& [u, v] : {std::pair<int, int>{0, 0}, {120, 70}, {240, 140}, {17, 101}}) {
    const Vec3d local = pose.inverse().transform(map.readingPoint(u, v));
    EXPECT_NEAR(local.x(), 4.0, 1e-5);
    const openvdb::math::Vec2d uv = map.project(local);
    EXPECT_NEAR(uv.x(), u, 1e-6);
    EXPECT_NEAR(uv.y(), v, 1e-6);
  }
  // A point 0.1 in front of the wall along its ray, and D's gradient by differences.
  const Vec3d ray = Vec3d(1.0, 0.3, 0.2).unit();
  const Vec3d x = pose.transform(ray * (4.0 / ray.x() - 0.1));
  RangeSample s;
  ASSERT_TRUE(map.sample(x, s));
  EXPECT_NEAR(s.D, -0.1, 2e-4);  // the bilinear readings of a plane bend by a little
  test::expectGradDByDifferences(map, x, s, 1e-5, 1e-3);
  // For a plane, grad D points along the wall's normal scaled by the ray's
  // slant: |grad D| = 1 / cos(incidence) at the wall.
  const Vec3d normal = pose.transform3x3(Vec3d(1, 0, 0));
  EXPECT_NEAR(s.gradD.unit().dot(normal), 1.0, 1e-3);
  // The fast path gives the same answers in the map's frame.
  RangeMap::LocalSample fast;
  ASSERT_TRUE(map.sampleLocal(map.worldToMap().transform(x), 1.0, fast));
  EXPECT_NEAR(fast.D, s.D, 1e-12);
  EXPECT_NEAR(fast.gamma, s.gamma, 1e-9 * s.gamma);
  EXPECT_FALSE(map.sampleLocal(map.worldToMap().transform(x), 0.05, fast));  // beyond the reach
}

TEST(SphericalRangeMap, SightAlongTheRays) {
  const Mat4d pose = scannerPose();
  RangeMap map = wall(pose);
  const Vec3d ray = Vec3d(1.0, -0.2, 0.1).unit();
  const double atWall = 4.0 / ray.x();
  EXPECT_EQ(map.sight(pose.transform(ray * (atWall - 0.5)), 0.05), RangeMap::Sight::kEmpty);
  EXPECT_EQ(map.sight(pose.transform(ray * (atWall + 0.5)), 0.05), RangeMap::Sight::kBehind);
  EXPECT_EQ(map.sight(pose.transform(ray * atWall), 0.05), RangeMap::Sight::kUnknown);
  EXPECT_EQ(map.sight(pose.transform(Vec3d(-3.0, 0.5, 0.0)), 0.05), RangeMap::Sight::kOutside);
  // The largest distance between rays at the readings: the farthest reading times the step.
  double farthest = 0.0;
  for (int v = 0; v < kRows; ++v)
    for (int u = 0; u < kColumns; ++u) farthest = std::max(farthest, double(map.reading(u, v)));
  EXPECT_NEAR(map.maxRaySpacing(), farthest * 0.5 * kDegree, 1e-6);
}

TEST(SphericalRangeMap, RangesFollowTheNoiseModel) {
  const DepthNoise noise{0.001, 0.0, 0.0005};  // 0.5 mm per metre of range, at least 1 mm
  const RangeMap map = RangeMap::spherical(kColumns, kRows, std::vector<float>(kColumns * kRows, 6.0f),
                                           halfDegreeGrid(), Mat4d::identity(), noise, "noisy");
  RangeSample s;
  ASSERT_TRUE(map.sample(Vec3d(6.0, 0.1, 0.1), s));
  EXPECT_NEAR(s.sigma, 0.0005 * 6.0, 1e-7);
  EXPECT_DOUBLE_EQ(map.sigma(), noise.at(1.0));
  ASSERT_NE(map.depthNoise(), nullptr);
}

TEST(SphericalRangeMap, RejectsImpossibleGrids) {
  const std::vector<float> ranges(16, 1.0f);
  const auto make = [&](const SphericalProjection& p, int width = 4, int height = 4) {
    return RangeMap::spherical(width, height, std::vector<float>(static_cast<std::size_t>(width * height), 1.0f), p,
                               Mat4d::identity(), 0.01, "bad");
  };
  EXPECT_THROW(make({0.0, 0.0, 0.0, 0.01}), std::invalid_argument);                     // no azimuth step
  EXPECT_THROW(make({0.0, 0.01, 0.0, std::nan("")}), std::invalid_argument);            // not finite
  EXPECT_THROW(make({0.0, 0.01, 80.0 * kDegree, 4.0 * kDegree}), std::invalid_argument);  // past the pole
  EXPECT_THROW(make({0.0, 0.01, -90.0 * kDegree, 0.01}), std::invalid_argument);          // at the pole
  EXPECT_THROW(make({0.0, 2.0 * M_PI / 3.0 + 0.01, 0.0, 0.01}), std::invalid_argument);   // more than a turn
  EXPECT_NO_THROW(make({0.0, 2.0 * M_PI / 3.0, 0.0, 0.01}));                             // a closed turn
  EXPECT_NO_THROW(make({0.0, -0.01, 0.3, -0.01}));                                        // sweeping backwards
}

/// Points of the wall x = 4 and the floor z = -1.5 around the scanner, on a
/// scanner's grid of `step` radians starting at the given phases.
std::vector<Vec3d> roomPoints(double step, double azimuthPhase, double elevationPhase, double azimuthSpan) {
  std::vector<Vec3d> points;
  for (double azimuth = azimuthPhase - 0.5 * azimuthSpan; azimuth < azimuthPhase + 0.5 * azimuthSpan - 1e-9;
       azimuth += step)
    for (double elevation = elevationPhase - 40.0 * kDegree; elevation < 40.0 * kDegree; elevation += step) {
      const Vec3d d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                    std::sin(elevation));
      double range = std::numeric_limits<double>::infinity();
      if (d.x() > 0.0) range = std::min(range, 4.0 / d.x());
      if (d.z() < 0.0) range = std::min(range, -1.5 / d.z());
      if (std::isfinite(range)) points.push_back(d * range);
      else points.emplace_back(0.0);  // no return
    }
  return points;
}

TEST(SphericalScan, BinningKeepsTheScannersGrid) {
  const double step = 0.25 * kDegree;
  const std::vector<Vec3d> points = roomPoints(step, 0.1 * kDegree, 0.07 * kDegree, 120.0 * kDegree);
  const RangeMap map = sphericalMapFromPoints(points, AngularSteps{step, step}, scannerPose(), 0.002, "room");
  EXPECT_EQ(map.kind(), RangeMap::Kind::kSpherical);
  // Every point has a pixel of its own, at its own direction.
  std::size_t returns = 0;
  for (const Vec3d& p : points) returns += p.lengthSqr() > 0.0;
  EXPECT_EQ(map.validCount(), returns);
  EXPECT_NEAR(map.sphericalProjection().azimuthStep, step, 1e-12);
  for (int v = 0; v < map.height(); v += 13)
    for (int u = 0; u < map.width(); u += 17) {
      if (!map.valid(u, v)) continue;
      const Vec3d local = scannerPose().inverse().transform(map.readingPoint(u, v));
      const bool onWall = std::fabs(local.x() - 4.0) < 1e-4, onFloor = std::fabs(local.z() + 1.5) < 1e-4;
      EXPECT_TRUE(onWall || onFloor) << u << " " << v << ": " << local;
    }
}

TEST(SphericalScan, AWholeTurnIsClosed) {
  const double step = 1.0 * kDegree;
  std::vector<Vec3d> points;
  for (int column = 0; column < 360; ++column)
    for (int row = -20; row <= 20; ++row) {
      const double azimuth = (column + 0.3) * step, elevation = row * step;
      points.push_back(Vec3d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                             std::sin(elevation)) *
                       3.0);  // a sphere of radius 3 around the scanner
    }
  const RangeMap map = sphericalMapFromPoints(points, AngularSteps{step * 1.0001, step}, Mat4d::identity(), 0.002);
  EXPECT_EQ(map.width(), 361);  // the first column again after the last
  EXPECT_EQ(map.height(), 41);
  EXPECT_NEAR(map.sphericalProjection().azimuthStep, step, 1e-12);  // a whole number of columns a turn
  // A step that does not divide the turn leaves the turn open.
  const RangeMap open = sphericalMapFromPoints(points, AngularSteps{step * 1.01, step}, Mat4d::identity(), 0.002);
  EXPECT_LE(open.width(), 357);
  EXPECT_NEAR(open.sphericalProjection().azimuthStep, step * 1.01, 1e-12);
  // The seam between the last column and the first is data like anywhere else.
  const double seam = map.sphericalProjection().azimuthStart - 0.5 * step;
  RangeSample s;
  ASSERT_TRUE(map.sample(Vec3d(std::cos(seam), std::sin(seam), 0.0) * 3.2, s));
  EXPECT_NEAR(s.D, 0.2, 1e-6);
}

TEST(SphericalScan, ASweepAcrossTheBackOfTheScannerKeepsItsColumns) {
  // 0.7 degree steps (no whole number of them in a turn) from 150 to 210
  // degrees of azimuth, across the cut of atan2 at 180: every point is a
  // reading at its own direction.
  const double step = 0.7 * kDegree;
  std::vector<Vec3d> points;
  for (int column = 0; column < 86; ++column)
    for (int row = 0; row < 20; ++row) {
      const double azimuth = (150.0 + 0.7 * column) * kDegree, elevation = (row - 10) * step;
      points.push_back(Vec3d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                             std::sin(elevation)) *
                       (2.0 + 0.01 * column));
    }
  const RangeMap map = sphericalMapFromPoints(points, AngularSteps{step, step}, Mat4d::identity(), 0.002);
  ASSERT_EQ(map.width(), 86);
  ASSERT_EQ(map.height(), 20);
  EXPECT_EQ(map.validCount(), points.size());
  for (int v = 0; v < map.height(); ++v)
    for (int u = 0; u < map.width(); ++u)
      ASSERT_NEAR((map.readingPoint(u, v) - points[static_cast<std::size_t>(u) * 20 + v]).length(), 0.0, 1e-5)
          << u << " " << v;
}

TEST(SphericalScan, ReadingsOffTheirPixelsCentresAreMovedThereAlongTheSurface) {
  // A line scanner's columns lean: the azimuth drifts by a step over a
  // column's 60 rows (as on the pump-room station), so its points lie up to
  // half a pixel off the centres of the map's regular grid. A wall seen at
  // 50 to 70 degrees of incidence: a reading left on its point's range along
  // its pixel's centre ray would stand off the wall by up to half the
  // distance between rays times sin(incidence).
  const double step = 0.5 * kDegree;
  std::vector<Vec3d> points;
  const int columns = 80, rows = 60;
  for (int column = 0; column < columns; ++column)
    for (int row = 0; row < rows; ++row) {
      const double azimuth = (30.0 + 0.5 * column) * kDegree + step * row / rows;
      const double elevation = (row - 30) * step;
      const Vec3d ray(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                      std::sin(elevation));
      points.push_back(ray * (2.0 / ray.x()));  // the wall x = 2
    }
  const RangeMap map =
      sphericalMapFromPoints(points, stepsOfGrid(points, columns, rows), Mat4d::identity(), 0.002, "leaning");
  const auto onWall = [&](int u, int v) { return std::fabs(map.readingPoint(u, v).x() - 2.0); };
  double farthest = 0.0, spacing = 0.0;
  int interior = 0;
  for (int v = 1; v + 1 < map.height(); ++v)
    for (int u = 1; u + 1 < map.width(); ++u) {
      if (!map.valid(u, v) || !map.valid(u - 1, v) || !map.valid(u + 1, v) || !map.valid(u, v - 1) ||
          !map.valid(u, v + 1))
        continue;
      ++interior;
      farthest = std::max(farthest, onWall(u, v));
      spacing = std::max(spacing, map.readingPoint(u, v).length() * step);
    }
  ASSERT_GT(interior, columns * rows / 2);
  EXPECT_LT(farthest, 0.02 * spacing) << "of a ray spacing of " << spacing << " m";
}

TEST(SphericalScan, AStationIsASceneWhoseRaysAreTypicallyAsFarApartAsAtItsMedianRange) {
  // A wedge of a room seen from a corner: the scanner stands outside the
  // readings' box, and the station is still a scene. Ranges 2 to 6 m along
  // a wall seen obliquely; azimuth steps four times the elevation steps.
  const double azimuthStep = 0.4 * kDegree, elevationStep = 0.1 * kDegree;
  std::vector<Vec3d> points;
  std::vector<double> ranges;
  for (int column = 0; column < 60; ++column)
    for (int row = 0; row < 200; ++row) {
      const double azimuth = (20.0 + 0.4 * column) * kDegree, elevation = (row - 100) * elevationStep;
      const Vec3d ray(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                      std::sin(elevation));
      points.push_back(ray * (1.0 / ray.y()));  // the wall y = 1, seen from 20 to 44 degrees of azimuth
      ranges.push_back(points.back().length());
    }
  const RangeMap map = sphericalMapFromPoints(points, AngularSteps{azimuthStep, elevationStep}, Mat4d::identity(),
                                              0.002, "wedge");
  EXPECT_FALSE(map.readingBounds().isInside(map.scannerPosition()));
  EXPECT_TRUE(map.ofAScene());
  std::nth_element(ranges.begin(), ranges.begin() + ranges.size() / 2, ranges.end());
  EXPECT_NEAR(map.typicalRaySpacing(), ranges[ranges.size() / 2] * std::sqrt(azimuthStep * elevationStep), 1e-3);
  EXPECT_GT(map.maxRaySpacing(), 2.0 * map.typicalRaySpacing());  // the farthest reading at the coarser step
}

TEST(SphericalScan, StepsOfAStructuredGrid) {
  const double step = 0.3 * kDegree;
  const std::vector<Vec3d> points = roomPoints(step, 0.0, 0.0, 90.0 * kDegree);
  // roomPoints lists a column of elevations after another: rows per column.
  int perColumn = 0;
  for (double elevation = -40.0 * kDegree; elevation < 40.0 * kDegree; elevation += step) ++perColumn;
  const int columns = static_cast<int>(points.size()) / perColumn;
  const AngularSteps steps = stepsOfGrid(points, columns, perColumn);
  EXPECT_NEAR(steps.azimuth, step, 1e-9);
  EXPECT_NEAR(steps.elevation, step, 1e-9);
  EXPECT_THROW(stepsOfGrid(points, columns + 1, perColumn), std::invalid_argument);
  EXPECT_THROW(stepsOfGrid(std::vector<Vec3d>(100, Vec3d(0.0)), 10, 10), std::invalid_argument);
}

TEST(SphericalScan, RejectsUnusablePointsAndSteps) {
  const std::vector<Vec3d> points = roomPoints(kDegree, 0.0, 0.0, 60.0 * kDegree);
  EXPECT_THROW(sphericalMapFromPoints(points, AngularSteps{0.0, kDegree}, Mat4d::identity(), 0.002),
               std::invalid_argument);
  EXPECT_THROW(sphericalMapFromPoints(points, AngularSteps{kDegree, -1.0}, Mat4d::identity(), 0.002),
               std::invalid_argument);
  // Steps far finer than the scanner's: a grid too large to hold.
  EXPECT_THROW(sphericalMapFromPoints(points, AngularSteps{1e-7, 1e-7}, Mat4d::identity(), 0.002),
               std::invalid_argument);
  // Only points at the poles or the scanner.
  EXPECT_THROW(sphericalMapFromPoints({Vec3d(0, 0, 1), Vec3d(0.0), Vec3d(0, 0, -2)}, AngularSteps{kDegree, kDegree},
                                      Mat4d::identity(), 0.002),
               std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse
