// Range maps against analytic answers.

#include "support/RangeSampleChecks.h"

#include <levelfuse/scan/RangeMap.h>

#include <openvdb/math/Vec3.h>

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

const float kNone = std::numeric_limits<float>::quiet_NaN();

/// A rigid map-to-world: a rotation about x by `angle`, then a translation.
Mat4d pose(double angle, const Vec3d& t) {
  Mat4d m = Mat4d::identity();
  m.preRotate(openvdb::math::X_AXIS, angle);
  m.setTranslation(t);
  return m;
}

/// An orthographic map of the tilted plane z = 2 + 0.5 x (map frame), 20 x 10 pixels of 0.1.
RangeMap tiltedPlane(const Mat4d& mapToWorld, float hole = 0.0f) {
  const OrthographicProjection projection{0.1, openvdb::math::Vec2d(-1.0, -0.5)};
  std::vector<float> readings;
  for (int v = 0; v < 10; ++v)
    for (int u = 0; u < 20; ++u) readings.push_back(float(2.0 + 0.5 * (-1.0 + 0.1 * u)));
  if (hole != 0.0f) readings[5 * 20 + 10] = hole;
  return RangeMap::orthographic(20, 10, readings, projection, mapToWorld, 0.01, "plane");
}

TEST(RangeMap, OrthographicGeometry) {
  const Mat4d m2w = pose(0.3, Vec3d(1.0, -2.0, 0.5));
  const RangeMap map = tiltedPlane(m2w);
  EXPECT_EQ(map.validCount(), 200u);
  // A point 0.2 behind the plane along the rays (+z of the map).
  const Vec3d local(0.05, 0.12, 2.0 + 0.5 * 0.05 + 0.2);
  RangeSample s;
  ASSERT_TRUE(map.sample(m2w.transform(local), s));
  EXPECT_NEAR(s.D, 0.2, 1e-6);
  // grad D = (-dr/dx, -dr/dy, 1) in the map frame, rotated to the world.
  const Vec3d grad = m2w.transform3x3(Vec3d(-0.5, 0.0, 1.0));
  EXPECT_NEAR((s.gradD - grad).length(), 0.0, 1e-6);
  EXPECT_NEAR((s.lineOfSight - m2w.transform3x3(Vec3d(0, 0, 1))).length(), 0.0, 1e-12);
  EXPECT_NEAR(s.gamma, 100.0, 1e-9);  // one ray per 0.1 x 0.1
  EXPECT_DOUBLE_EQ(s.sigma, 0.01);
  // In front of the reading, D < 0; a reading's own point has D = 0.
  ASSERT_TRUE(map.sample(m2w.transform(local - Vec3d(0, 0, 0.5)), s));
  EXPECT_NEAR(s.D, -0.3, 1e-6);
  ASSERT_TRUE(map.sample(map.readingPoint(7, 3), s));
  EXPECT_NEAR(s.D, 0.0, 1e-6);
  // Outside the map: no data.
  EXPECT_FALSE(map.sample(m2w.transform(Vec3d(5.0, 0.0, 2.0)), s));
}

TEST(RangeMap, ColoursAreInterpolatedAsTheReadingsAre) {
  RangeMap map = tiltedPlane(Mat4d::identity());
  EXPECT_FALSE(map.hasColours());
  openvdb::Vec3f rgb;
  EXPECT_FALSE(map.colourAt(map.worldToMap().transform(map.readingPoint(3, 3)), rgb));
  EXPECT_THROW(map.setColours(std::vector<Rgb8>(7)), std::invalid_argument);
  // Red rising with the column, blue with the row.
  std::vector<Rgb8> colours;
  for (int v = 0; v < map.height(); ++v)
    for (int u = 0; u < map.width(); ++u)
      colours.push_back(Rgb8{static_cast<std::uint8_t>(10 * u), 0, static_cast<std::uint8_t>(20 * v)});
  map.setColours(colours);
  ASSERT_TRUE(map.hasColours());
  // A quarter of the way from pixel (4, 2) to (5, 3), on the line of sight.
  const Vec3d p = map.worldToMap().transform(map.pointAt(4.25, 2.25, 2.0));
  ASSERT_TRUE(map.colourAt(p, rgb));
  EXPECT_NEAR(rgb[0], 42.5 / 255.0, 1e-6);
  EXPECT_NEAR(rgb[1], 0.0, 1e-6);
  EXPECT_NEAR(rgb[2], 45.0 / 255.0, 1e-6);
  // None beside the map.
  EXPECT_FALSE(map.colourAt(Vec3d(50.0, 0.0, 2.0), rgb));
}

TEST(RangeMap, ResampledFromSamplesKeepsTheScannersRayDensity) {
  const Mat4d m2w = pose(0.3, Vec3d(1.0, -2.0, 0.5));
  RangeMap map = tiltedPlane(m2w);  // pixels 0.1 apart
  const Vec3d local(0.05, 0.12, 2.0 + 0.5 * 0.05 + 0.2);
  RangeSample before, after;
  ASSERT_TRUE(map.sample(m2w.transform(local), before));
  EXPECT_EQ(map.sampleCount(), map.validCount());  // without samples, the readings are the samples
  // The map resamples samples taken 0.2 apart: four pixels per ray.
  map.setSamples({m2w.transform(Vec3d(0.0, 0.0, 2.0)), m2w.transform(Vec3d(0.2, 0.0, 2.1))}, 0.2);
  EXPECT_EQ(map.sampleCount(), 2u);
  EXPECT_NEAR(map.maxRaySpacing(), 0.2, 1e-12);
  ASSERT_TRUE(map.sample(m2w.transform(local), after));
  EXPECT_NEAR(after.gamma, 25.0, 1e-9);  // one ray per 0.2 x 0.2, whatever the pixels
  EXPECT_EQ(after.D, before.D);
  RangeMap::LocalSample fast;
  ASSERT_TRUE(map.sampleLocal(local, 1.0, fast));
  EXPECT_NEAR(fast.gamma, 25.0, 1e-9);
  EXPECT_THROW(map.setSamples({Vec3d(0.0, NAN, 0.0)}, 0.2), std::invalid_argument);
  EXPECT_THROW(map.setSamples({Vec3d(0.0)}, 0.0), std::invalid_argument);
  RangeMap camera = RangeMap::pinhole(4, 4, std::vector<float>(16, 1.0f), PinholeProjection{2, 2, 1.5, 1.5},
                                      Mat4d::identity(), 0.01, "camera");
  EXPECT_THROW(camera.setSamples({Vec3d(0.0, 0.0, 1.0)}, 0.1), std::invalid_argument);
}

TEST(RangeMap, NeverInterpolatesAcrossMissingReadingsOrSteps) {
  RangeSample s;
  const RangeMap holed = tiltedPlane(Mat4d::identity(), kNone);
  // The four cells around pixel (10, 5) touch the hole; the others do not.
  const Vec3d nearHole(-1.0 + 0.1 * 10 - 0.05, -0.5 + 0.1 * 5 + 0.05, 2.5);
  EXPECT_FALSE(holed.sample(nearHole, s));
  EXPECT_TRUE(holed.sample(nearHole + Vec3d(0.3, 0.0, 0.0), s));
  EXPECT_EQ(holed.validCount(), 199u);
  // A reading 1.0 further than its neighbours (10 ray spacings): a discontinuity.
  const RangeMap stepped = tiltedPlane(Mat4d::identity(), 3.5f);
  EXPECT_FALSE(stepped.sample(nearHole, s));
  // A gentle slope is not a step.
  EXPECT_TRUE(tiltedPlane(Mat4d::identity()).sample(nearHole, s));
}

TEST(RangeMap, PinholeGeometry) {
  // A fronto-parallel wall at depth 2 seen by a 40 x 30 camera.
  const PinholeProjection k{50.0, 50.0, 19.5, 14.5};
  const Mat4d c2w = pose(-0.2, Vec3d(0.1, 0.2, 0.3));
  const RangeMap map = RangeMap::pinhole(40, 30, std::vector<float>(40 * 30, 2.0f), k, c2w, 0.002, "wall");
  // Along the ray through pixel (30, 20), a point 0.1 (along the ray) behind the wall.
  const Vec3d ray = Vec3d((30 - 19.5) / 50.0, (20 - 14.5) / 50.0, 1.0);
  const Vec3d onWall = ray * 2.0;
  const Vec3d behind = onWall + ray.unit() * 0.1;
  RangeSample s;
  ASSERT_TRUE(map.sample(c2w.transform(behind), s));
  EXPECT_NEAR(s.D, 0.1, 1e-6);
  EXPECT_NEAR((s.lineOfSight - c2w.transform3x3(ray.unit())).length(), 0.0, 1e-9);
  // gamma: rays per unit area across the ray, fx fy / (|p|^2 cos^3 theta).
  const double cosTheta = 1.0 / ray.length();
  EXPECT_NEAR(s.gamma, 2500.0 / (behind.lengthSqr() * std::pow(cosTheta, 3)), 1e-6 * s.gamma);
  // D along the ray is |p| - |reading|: its gradient is the ray direction for a flat wall.
  test::expectGradDByDifferences(map, c2w.transform(behind), s, 1e-6, 1e-4);
  // Behind the camera: nothing.
  EXPECT_FALSE(map.sample(c2w.transform(Vec3d(0, 0, -1)), s));
  // Depths <= 0 are missing readings.
  std::vector<float> depths(40 * 30, 1.0f);
  depths[7] = 0.0f;
  depths[8] = -2.0f;
  EXPECT_EQ(RangeMap::pinhole(40, 30, depths, k, c2w, 0.002).validCount(), 40u * 30u - 2u);
}

/// The box of every reading's world point (readingPoint), as readingBounds should hold it.
openvdb::BBoxd boxOfReadingPoints(const RangeMap& map) {
  openvdb::BBoxd box;
  for (int v = 0; v < map.height(); ++v)
    for (int u = 0; u < map.width(); ++u)
      if (map.valid(u, v)) box.expand(map.readingPoint(u, v));
  return box;
}

TEST(RangeMap, ReadingBoundsAreTheBoxOfEveryReadingsPointExactly) {
  // Uneven depths with holes, seen by a tilted camera off the origin: the
  // box is worked out once, with each column's slope shared, and must hold
  // the very points readingPoint gives.
  const PinholeProjection k{52.5, 49.0, 19.25, 14.75};
  const Mat4d c2w = pose(-0.7, Vec3d(0.1, -2.2, 0.3));
  std::vector<float> depths(40 * 30);
  for (int v = 0; v < 30; ++v)
    for (int u = 0; u < 40; ++u) depths[v * 40 + u] = float(1.0 + 0.037 * u + 0.011 * v * v + 0.3 * std::sin(0.7 * u));
  depths[0] = depths[39] = depths[40 * 29 + 7] = kNone;
  const RangeMap camera = RangeMap::pinhole(40, 30, depths, k, c2w, 0.002, "uneven");
  const openvdb::BBoxd expected = boxOfReadingPoints(camera);
  EXPECT_EQ(camera.readingBounds().min(), expected.min());
  EXPECT_EQ(camera.readingBounds().max(), expected.max());
  // Parallel rays take the general way.
  const RangeMap plane = tiltedPlane(pose(0.4, Vec3d(1.0, 2.0, 3.0)), kNone);
  EXPECT_EQ(plane.readingBounds().min(), boxOfReadingPoints(plane).min());
  EXPECT_EQ(plane.readingBounds().max(), boxOfReadingPoints(plane).max());
}

TEST(RangeMap, DepthNoiseIsTheSigmaPerPixelOfTheReadingsDepth) {
  // A floor seen from 1 to 3.4 m, a few readings missing: the sigmas computed
  // from the depth are those a sigma per pixel gives, at every sample.
  const PinholeProjection k{50.0, 50.0, 19.5, 14.5};
  const Mat4d c2w = pose(-0.2, Vec3d(0.1, 0.2, 0.3));
  std::vector<float> depths(40 * 30);
  for (std::size_t i = 0; i < depths.size(); ++i) depths[i] = 1.0f + 0.08f * static_cast<float>(i / 40);
  depths[101] = std::numeric_limits<float>::quiet_NaN();
  const DepthNoise noise{0.001, 0.0015};
  std::vector<float> sigmas(depths.size());
  for (std::size_t i = 0; i < depths.size(); ++i) {
    const double z = depths[i] == depths[i] ? depths[i] : 1.0;
    sigmas[i] = static_cast<float>(std::max(noise.minimum, noise.perSquareMetre * z * z));
  }
  RangeMap perPixel = RangeMap::pinhole(40, 30, depths, k, c2w, 0.002, "floor");
  RangeMap modelled = perPixel;
  perPixel.setSigmas(sigmas);
  modelled.setDepthNoise(noise);
  std::size_t sampled = 0;
  for (int u = 0; u < 39; ++u)
    for (int v = 0; v < 29; ++v) {
      const Vec3d ray((u + 0.3 - 19.5) / 50.0, (v + 0.6 - 14.5) / 50.0, 1.0);
      const Vec3d x = c2w.transform(ray * (1.0 + 0.08 * v + 0.01));
      RangeSample a, b;
      const bool seen = perPixel.sample(x, a);
      ASSERT_EQ(seen, modelled.sample(x, b)) << u << " " << v;
      if (!seen) continue;
      EXPECT_EQ(a.sigma, b.sigma) << u << " " << v;
      ++sampled;
    }
  EXPECT_GT(sampled, 900u);
  EXPECT_GT(modelled.sigma(), 0.0);
  EXPECT_THROW(modelled.setDepthNoise(DepthNoise{0.0, 0.0015}), std::invalid_argument);
  EXPECT_THROW(modelled.setDepthNoise(DepthNoise{0.001, -1.0}), std::invalid_argument);
}

TEST(RangeMap, FastPathAgreesWithTheFullSample) {
  const Mat4d m2w = pose(0.7, Vec3d(0.3, 0.1, -0.2));
  const RangeMap map = tiltedPlane(m2w);
  for (double dz : {-0.4, -0.1, 0.0, 0.15}) {
    const Vec3d local(-0.33, 0.21, 2.0 + 0.5 * -0.33 + dz);
    RangeSample full;
    RangeMap::LocalSample fast;
    ASSERT_TRUE(map.sample(m2w.transform(local), full));
    ASSERT_TRUE(map.sampleLocal(map.worldToMap().transform(m2w.transform(local)), 1.0, fast));
    EXPECT_NEAR(fast.D, full.D, 1e-9);
    EXPECT_NEAR(fast.gradDSquared, full.gradD.lengthSqr(), 1e-9);
    EXPECT_NEAR(fast.gamma, full.gamma, 1e-9);
    EXPECT_FALSE(map.sampleLocal(map.worldToMap().transform(m2w.transform(local)), std::fabs(dz) * 0.5, fast) &&
                 dz != 0.0);
  }
}

TEST(RangeMap, RejectsInconsistentInput) {
  const OrthographicProjection p{0.1, openvdb::math::Vec2d(0.0)};
  EXPECT_THROW(RangeMap::orthographic(4, 4, std::vector<float>(15, 1.0f), p, Mat4d::identity(), 0.01),
               std::invalid_argument);
  EXPECT_THROW(RangeMap::orthographic(4, 4, std::vector<float>(16, 1.0f), OrthographicProjection{0.0, {}},
                                      Mat4d::identity(), 0.01),
               std::invalid_argument);
  EXPECT_THROW(RangeMap::orthographic(4, 4, std::vector<float>(16, 1.0f), p, Mat4d::identity(), 0.0),
               std::invalid_argument);
  Mat4d scaled = Mat4d::identity();
  scaled.preScale(Vec3d(2.0));
  EXPECT_THROW(RangeMap::orthographic(4, 4, std::vector<float>(16, 1.0f), p, scaled, 0.01), std::invalid_argument);
  Mat4d mirrored = Mat4d::identity();
  mirrored.preScale(Vec3d(1.0, 1.0, -1.0));
  EXPECT_THROW(RangeMap::orthographic(4, 4, std::vector<float>(16, 1.0f), p, mirrored, 0.01), std::invalid_argument);
  EXPECT_THROW(RangeMap::pinhole(4, 4, std::vector<float>(16, 1.0f), PinholeProjection{0.0, 1.0, 0.0, 0.0},
                                 Mat4d::identity(), 0.01),
               std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse
