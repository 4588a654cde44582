// estimateAngularSteps: the steps of unordered points from synthetic scanners
// (a terrestrial scanner's equal steps, a spinning LiDAR's rows, uneven rows,
// jitter, missing returns, partial sweeps, points at many ranges), and the
// range maps they bin into.

#include "support/ScannerPoses.h"

#include <levelfuse/scan/SphericalScan.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

using test::kDegree;

/// A scanner's rays: rows of elevations, each swept along the same azimuths.
struct SyntheticScanner {
  std::vector<double> elevations;  ///< radians, one per row
  double azimuthStart = 0.0, azimuthStep = 0.0;
  int columns = 0;
  double jitter = 0.0;   ///< of each angle, uniform within +-jitter steps
  double missing = 0.0;  ///< fraction of rays without a return
};

std::vector<double> evenRows(double lowest, double step, int rows) {
  std::vector<double> elevations;
  for (int r = 0; r < rows; ++r) elevations.push_back(lowest + r * step);
  return elevations;
}

/// The scanner's points, at ranges from 1 to 80 m, shuffled (unordered).
std::vector<Vec3d> pointsOf(const SyntheticScanner& s, unsigned seed = 7) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3d> points;
  const double elevationStep = s.elevations.size() > 1 ? std::fabs(s.elevations[1] - s.elevations[0]) : 0.0;
  for (const double elevation : s.elevations)
    for (int c = 0; c < s.columns; ++c) {
      const double azimuth = s.azimuthStart + c * s.azimuthStep + (2.0 * unit(random) - 1.0) * s.jitter * s.azimuthStep;
      const double e = elevation + (2.0 * unit(random) - 1.0) * s.jitter * elevationStep;
      const double range = 1.0 + 79.0 * unit(random);
      if (unit(random) < s.missing) continue;
      points.emplace_back(range * std::cos(e) * std::cos(azimuth), range * std::cos(e) * std::sin(azimuth),
                          range * std::sin(e));
    }
  std::shuffle(points.begin(), points.end(), random);
  return points;
}

/// A Velodyne HDL-64E's sweep: 64 rows 0.4 degrees apart from 2 degrees
/// down, a whole turn of 2117 columns (0.17 degrees).
SyntheticScanner velodyne() {
  SyntheticScanner s;
  s.elevations = evenRows(2.0 * kDegree - 63 * 0.4 * kDegree, 0.4 * kDegree, 64);
  s.azimuthStart = -M_PI;
  s.columns = 2117;
  s.azimuthStep = 2.0 * M_PI / s.columns;
  return s;
}

void expectSteps(const AngularSteps& steps, double azimuth, double elevation, double relative) {
  EXPECT_NEAR(steps.azimuth, azimuth, relative * azimuth) << steps.azimuth / kDegree << " degrees";
  EXPECT_NEAR(steps.elevation, elevation, relative * elevation) << steps.elevation / kDegree << " degrees";
}

/// The share of the points that keep a pixel of their own on the map.
double pointsKept(const std::vector<Vec3d>& points, const AngularSteps& steps) {
  const RangeMap map = sphericalMapFromPoints(points, steps, openvdb::math::Mat4d::identity(), 0.01);
  return static_cast<double>(map.validCount()) / static_cast<double>(points.size());
}

TEST(EstimateAngularSteps, ATerrestrialScannersEqualStepsOfATenthOfADegree) {
  SyntheticScanner s;
  s.elevations = evenRows(-30.0 * kDegree, 0.1 * kDegree, 301);
  s.azimuthStart = 10.0 * kDegree;  // a partial sweep of 60 degrees
  s.azimuthStep = 0.1 * kDegree;
  s.columns = 600;
  const std::vector<Vec3d> points = pointsOf(s);
  const AngularSteps steps = estimateAngularSteps(points);
  expectSteps(steps, 0.1 * kDegree, 0.1 * kDegree, 1e-6);
  EXPECT_GE(pointsKept(points, steps), 0.999);
}

TEST(EstimateAngularSteps, ASpinningLidarsRowsAndColumnsOfDifferentSteps) {
  const std::vector<Vec3d> points = pointsOf(velodyne());
  const AngularSteps steps = estimateAngularSteps(points);
  expectSteps(steps, 2.0 * M_PI / 2117, 0.4 * kDegree, 1e-6);
  EXPECT_GE(pointsKept(points, steps), 0.999);
}

// An HDL-64E's upper block of 32 lasers a third of a degree apart, and its
// lower block half a degree apart: the finer spacing, so that no two rows
// share a row of pixels.
TEST(EstimateAngularSteps, UnevenRowsTakeTheFinerSpacingAndKeepEveryPoint) {
  SyntheticScanner s = velodyne();
  s.elevations.clear();
  for (int r = 0; r < 32; ++r) s.elevations.push_back((2.0 - r / 3.0) * kDegree);
  for (int r = 0; r < 32; ++r) s.elevations.push_back((2.0 - 31.0 / 3.0 - 0.5 - 0.5 * r) * kDegree);
  std::sort(s.elevations.begin(), s.elevations.end());
  const std::vector<Vec3d> points = pointsOf(s);
  const AngularSteps steps = estimateAngularSteps(points);
  expectSteps(steps, 2.0 * M_PI / 2117, kDegree / 3.0, 1e-6);
  EXPECT_GE(pointsKept(points, steps), 0.999);
}

TEST(EstimateAngularSteps, AJitterOfATwentiethOfAStep) {
  SyntheticScanner s = velodyne();
  s.jitter = 0.05;
  const AngularSteps steps = estimateAngularSteps(pointsOf(s));
  expectSteps(steps, 2.0 * M_PI / 2117, 0.4 * kDegree, 0.01);
}

TEST(EstimateAngularSteps, ThirtyPercentOfTheReturnsMissing) {
  SyntheticScanner s = velodyne();
  s.missing = 0.3;
  const std::vector<Vec3d> points = pointsOf(s);
  const AngularSteps steps = estimateAngularSteps(points);
  expectSteps(steps, 2.0 * M_PI / 2117, 0.4 * kDegree, 1e-6);
  EXPECT_GE(pointsKept(points, steps), 0.999);
}

TEST(EstimateAngularSteps, JitterAndMissingReturnsOnATerrestrialGrid) {
  SyntheticScanner s;
  s.elevations = evenRows(-40.0 * kDegree, 0.25 * kDegree, 200);
  s.azimuthStart = -170.0 * kDegree;
  s.azimuthStep = 0.25 * kDegree;
  s.columns = 400;
  s.jitter = 0.05;
  s.missing = 0.3;
  expectSteps(estimateAngularSteps(pointsOf(s)), 0.25 * kDegree, 0.25 * kDegree, 0.01);
}

// More than a million points: the elevations are sampled, the steps the same.
TEST(EstimateAngularSteps, ALargeScanIsSampledEvenly) {
  SyntheticScanner s;
  s.elevations = evenRows(-20.0 * kDegree, 0.05 * kDegree, 1001);
  s.azimuthStart = 30.0 * kDegree;
  s.azimuthStep = 0.05 * kDegree;
  s.columns = 1200;
  const std::vector<Vec3d> points = pointsOf(s);
  ASSERT_GT(points.size(), 1000000u);
  const AngularSteps steps = estimateAngularSteps(points);
  expectSteps(steps, 0.05 * kDegree, 0.05 * kDegree, 1e-6);
  const AngularSteps again = estimateAngularSteps(points);
  EXPECT_EQ(again.azimuth, steps.azimuth);
  EXPECT_EQ(again.elevation, steps.elevation);
}

// Points without rows (a cloud thinned at random): both steps the mean
// spacing, a point per pixel, so that most keep a pixel of their own.
TEST(EstimateAngularSteps, ScatteredDirectionsTakeTheirMeanSpacing) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3d> points;
  const int count = 40000;
  for (int i = 0; i < count; ++i) {  // uniform over a patch of 40 x 30 degrees (of sphere)
    const double azimuth = 40.0 * kDegree * unit(random);
    const double elevation = std::asin(std::sin(-10.0 * kDegree) + (std::sin(20.0 * kDegree) - std::sin(-10.0 * kDegree)) * unit(random));
    points.push_back(Vec3d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                           std::sin(elevation)) * (2.0 + unit(random)));
  }
  const double solidAngle = 40.0 * kDegree * (std::sin(20.0 * kDegree) - std::sin(-10.0 * kDegree));
  const double spacing = std::sqrt(solidAngle / count);
  const AngularSteps steps = estimateAngularSteps(points);
  expectSteps(steps, spacing, spacing, 0.1);
  EXPECT_GT(pointsKept(points, steps), 0.5);
}

TEST(EstimateAngularSteps, TooFewPointsOrAllInOneDirectionAreRefused) {
  std::vector<Vec3d> few;
  for (int i = 0; i < 15; ++i) few.emplace_back(1.0, 0.01 * i, 0.02 * i);
  few.emplace_back(0.0, 0.0, 0.0);  // at the scanner: no direction
  few.emplace_back(0.0, 0.0, 5.0);  // at a pole
  EXPECT_THROW(estimateAngularSteps(few), std::invalid_argument);
  const std::vector<Vec3d> oneWay(100, Vec3d(1.0, 2.0, 0.5));
  try {
    estimateAngularSteps(oneWay);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("all the points lie in one direction"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace levelfuse
