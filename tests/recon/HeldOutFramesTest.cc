// A surface measured against depth frames of known surfaces.

#include "support/TestSupport.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/recon/HeldOutFrames.h>
#include <levelfuse/synth/Synth.h>

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

/// The plane z = slope x + offset as a square of two triangles, 40 units a side.
TriangleMesh planeMesh(double offset, double slope = 0.0) {
  TriangleMesh mesh;
  for (const double y : {-20.0, 20.0})
    for (const double x : {-20.0, 20.0})
      for (const double c : {x, y, slope * x + offset}) mesh.xyz.push_back(static_cast<float>(c));
  mesh.triangles = {0, 1, 3, 0, 3, 2};
  return mesh;
}

/// A depth camera 2 units above the plane z = 0, looking down at it obliquely: every pixel sees it.
RangeMap frameOfPlane(int width = 160, int height = 120) {
  const synth::View view = synth::pinholeView(Vec3d(0.7, -0.4, 2.0), Vec3d(0.0), 50.0, width, height, "plane");
  return synth::renderDistanceFunction([](const Vec3d& p) { return p.z(); }, view, synth::Noise{}, 0.001);
}

TEST(HeldOutFramesTest, AFrameOfTheSurfaceLiesOnIt) {
  const std::vector<RangeMap> frames{frameOfPlane()};
  const HeldOutAccuracy accuracy = measureHeldOutFrames(planeMesh(0.0), frames);
  EXPECT_EQ(accuracy.distances.readings, frames[0].validCount());
  EXPECT_EQ(accuracy.distances.readings, 160u * 120u);
  EXPECT_LT(accuracy.distances.mean, 1e-5);
  EXPECT_LT(accuracy.distances.p90, 1e-5);
  for (const double share : accuracy.within) EXPECT_EQ(share, 1.0);
}

TEST(HeldOutFramesTest, AnOffsetSurfaceIsTheOffsetAway) {
  const std::vector<RangeMap> frames{frameOfPlane()};
  const HeldOutAccuracy accuracy = measureHeldOutFrames(planeMesh(0.03), frames);
  EXPECT_NEAR(accuracy.distances.mean, 0.03, 1e-5);
  EXPECT_NEAR(accuracy.distances.median, 0.03, 1e-5);
  EXPECT_NEAR(accuracy.distances.p90, 0.03, 1e-5);
  EXPECT_EQ(accuracy.thresholds, (std::array<double, 3>{0.01, 0.02, 0.05}));
  EXPECT_EQ(accuracy.within, (std::array<double, 3>{0.0, 0.0, 1.0}));  // 3 cm: beyond 1 and 2 cm, within 5
}

TEST(HeldOutFramesTest, SharesCountThePointsWithinEachThreshold) {
  // A tilted plane through the frame's plane: each point's distance is
  // |slope x| / sqrt(1 + slope^2), counted here point by point.
  const std::vector<RangeMap> frames{frameOfPlane()};
  const double slope = 0.05;
  HeldOutOptions options;
  options.stride = 3;
  options.thresholds = {0.004, 0.012, 0.03};
  std::array<std::size_t, 3> expected{};
  std::size_t points = 0;
  for (int v = 0; v < frames[0].height(); v += 3)
    for (int u = 0; u < frames[0].width(); u += 3) {
      const Vec3d p = frames[0].readingPoint(u, v);
      const double distance = std::fabs(p.z() - slope * p.x()) / std::sqrt(1.0 + slope * slope);
      ++points;
      for (std::size_t k = 0; k < 3; ++k) expected[k] += distance <= options.thresholds[k];
    }
  const HeldOutAccuracy accuracy = measureHeldOutFrames(planeMesh(0.0, slope), frames, options);
  ASSERT_EQ(accuracy.distances.readings, points);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_GT(expected[k], 0u);
    EXPECT_LT(expected[k], points);  // each threshold splits the points
    // A point within 1e-6 of a threshold may fall either side of it.
    EXPECT_NEAR(accuracy.within[k], static_cast<double>(expected[k]) / static_cast<double>(points), 2.0 / points) << k;
  }
}

TEST(HeldOutFramesTest, MeasuresTheZeroSetOfALevelSet) {
  // A sphere of radius 1 (50 voxels) seen by a depth camera, against level
  // sets of radius 1 and 0.97: distances 0 and 0.03 but for the mesh's chords.
  const shapes::Sphere sphere{Vec3d(0.0), 1.0};
  const synth::View view = synth::pinholeView(Vec3d(0.5, 3.0, 2.0), Vec3d(0.0), 40.0, 120, 90, "sphere");
  const std::vector<RangeMap> frames{synth::renderDistanceFunction(sphere, view, synth::Noise{}, 0.001)};
  const double voxel = 0.02;
  const HeldOutAccuracy on = measureHeldOutFrames(*test::makeSphere(50.0, Vec3d(0.0), voxel), frames);
  EXPECT_EQ(on.distances.readings, frames[0].validCount());
  EXPECT_LT(on.distances.mean, 0.01 * voxel);
  const HeldOutAccuracy inside = measureHeldOutFrames(*test::makeSphere(48.5, Vec3d(0.0), voxel), frames);
  EXPECT_NEAR(inside.distances.mean, 0.03, 0.01 * voxel);
  EXPECT_EQ(inside.within, (std::array<double, 3>{0.0, 0.0, 1.0}));
}

TEST(HeldOutFramesTest, RefusesBadArguments) {
  const std::vector<RangeMap> frames{frameOfPlane(40, 30)};
  const TriangleMesh mesh = planeMesh(0.0);
  EXPECT_THROW(measureHeldOutFrames(mesh, std::vector<RangeMap>{}), std::invalid_argument);
  EXPECT_THROW(measureHeldOutFrames(TriangleMesh{}, frames), std::invalid_argument);
  HeldOutOptions options;
  options.stride = 0;
  EXPECT_THROW(measureHeldOutFrames(mesh, frames, options), std::invalid_argument);
  for (const double bad : {0.0, -0.01, std::numeric_limits<double>::quiet_NaN(), HUGE_VAL}) {
    options = HeldOutOptions();
    options.thresholds[1] = bad;
    EXPECT_THROW(measureHeldOutFrames(mesh, frames, options), std::invalid_argument) << bad;
  }
  const std::vector<RangeMap> orthographic{synth::renderDistanceFunction(
      [](const Vec3d& p) { return p.z(); }, synth::orthographicView(Vec3d(0, 0, -1), Vec3d(0.0), 1.0, 20),
      synth::Noise{}, 0.001)};
  EXPECT_THROW(measureHeldOutFrames(mesh, orthographic), std::invalid_argument);
  openvdb::FloatGrid fog;
  fog.setGridClass(openvdb::GRID_FOG_VOLUME);
  EXPECT_THROW(measureHeldOutFrames(fog, frames), std::invalid_argument);
  EXPECT_THROW(measureHeldOutFrames(openvdb::FloatGrid(3.0f), frames), std::invalid_argument);  // not a level set
}

TEST(HeldOutFramesTest, FramesWithoutReadingsMeasureNothing) {
  const synth::View view = synth::pinholeView(Vec3d(0.0, 0.0, 2.0), Vec3d(0.0, 0.0, 3.0), 50.0, 40, 30, "sky");
  const std::vector<RangeMap> frames{synth::renderDistanceFunction([](const Vec3d& p) { return p.z(); }, view,
                                                                   synth::Noise{}, 0.001)};  // looks away from it
  ASSERT_EQ(frames[0].validCount(), 0u);
  const HeldOutAccuracy accuracy = measureHeldOutFrames(planeMesh(0.0), frames);
  EXPECT_EQ(accuracy.distances.readings, 0u);
  EXPECT_EQ(accuracy.within, (std::array<double, 3>{0.0, 0.0, 0.0}));
}

TEST(HeldOutFramesTest, OneAndTwoThreadsAgree) {
  const std::vector<RangeMap> frames{frameOfPlane(100, 80), frameOfPlane(60, 40)};
  // A ball of radius 0.4 above the plane: the points lie 0.2 to 2 from it, most beyond the rings of cells.
  const TriangleMesh mesh = meshFromLevelSet(*test::makeSphere(8.0, Vec3d(0.1, 0.0, 0.6), 0.05));
  HeldOutAccuracy result[2];
  for (const int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    result[threads - 1] = measureHeldOutFrames(mesh, frames);
  }
  EXPECT_GT(result[0].distances.readings, 10000u);  // many chunks of the parallel loop
  EXPECT_EQ(result[0].distances.readings, result[1].distances.readings);
  EXPECT_EQ(result[0].distances.mean, result[1].distances.mean);
  EXPECT_EQ(result[0].distances.rms, result[1].distances.rms);
  EXPECT_EQ(result[0].distances.median, result[1].distances.median);
  EXPECT_EQ(result[0].distances.p90, result[1].distances.p90);
  EXPECT_EQ(result[0].within, result[1].within);
}

TEST(HeldOutFramesTest, SplitsFramesEveryKth) {
  const FrameSplit split = splitFrames(12, 5, 2);
  EXPECT_EQ(split.heldOut, (std::vector<std::size_t>{2, 7}));
  EXPECT_EQ(split.reconstruction, (std::vector<std::size_t>{0, 1, 3, 4, 5, 6, 8, 9, 10, 11}));
  EXPECT_TRUE(splitFrames(0, 3).heldOut.empty());
  EXPECT_THROW(splitFrames(10, 0), std::invalid_argument);
  EXPECT_THROW(splitFrames(10, 3, 3), std::invalid_argument);
  EXPECT_THROW(splitFrames(10, 3, -1), std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse
