// A range map packed and unpacked is the same map, and takes less memory.

#include "support/TestSupport.h"

#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/scan/PackedRangeMap.h>
#include <levelfuse/scan/RangeMap.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

/// A depth frame of a room's corner: two walls and a floor at depths quantised
/// to millimetres, as a 16-bit depth image gives them, with noise and holes.
RangeMap cornerFrame() {
  const int width = 160, height = 120;
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 2.0);  // mm
  std::vector<float> depths(static_cast<std::size_t>(width) * height);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const double wall = u < width / 2 ? 2000.0 + 8.0 * u : 2640.0 - 8.0 * (u - width / 2);
      const double depth = v > 90 ? std::min(wall, 1500.0 + 12.0 * (height - v)) : wall;
      const bool hole = (u * 7 + v * 3) % 97 == 0 || (u > 120 && v < 10);
      depths[static_cast<std::size_t>(v) * width + u] =
          hole ? 0.0f : static_cast<float>(std::round(depth + noise(random)) * 0.001);
    }
  openvdb::math::Mat4d pose = openvdb::math::Mat4d::identity();
  pose.setToRotation(openvdb::math::Y_AXIS, 0.3);
  pose.setTranslation(Vec3d(0.2, -0.1, 0.4));
  RangeMap map = RangeMap::pinhole(width, height, depths, PinholeProjection{150.0, 150.0, 79.5, 59.5}, pose, 0.002,
                                   "corner");
  map.setDepthNoise(DepthNoise{});
  map.setReadingStep(0.001);  // as io::depthFrame says of a PNG's millimetres
  return map;
}

/// Parallel rays with everything a map can hold per pixel: sigmas, ray
/// directions, samples, misses that are empty.
RangeMap everythingPerPixel() {
  const int size = 40;
  const double pixel = 0.05;
  std::vector<float> readings(static_cast<std::size_t>(size) * size), sigmas(readings.size());
  std::vector<openvdb::Vec3f> directions(readings.size());
  std::vector<Vec3d> samples;
  for (int v = 0; v < size; ++v)
    for (int u = 0; u < size; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * size + u;
      const double x = -1.0 + u * pixel, y = -1.0 + v * pixel;
      const bool missed = x * x + y * y > 0.8;
      readings[i] = missed ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(1.0 + 0.3 * std::sin(3 * x * y));
      sigmas[i] = static_cast<float>(0.001 + 0.0001 * u);
      directions[i] = openvdb::Vec3f(0.01f * float(u - 20), 0.0f, 1.0f).unitSafe();
      if (!missed) samples.emplace_back(x, y, readings[i]);
    }
  RangeMap map = RangeMap::orthographic(size, size, readings, OrthographicProjection{pixel, openvdb::math::Vec2d(-1.0, -1.0)},
                                        openvdb::math::Mat4d::identity(), 0.002, "dome");
  map.setSigmas(sigmas);
  map.setRayDirections(directions);
  map.setSamples(samples, pixel);
  map.setMissesAreEmpty(true);
  std::vector<Rgb8> colours(readings.size());
  for (std::size_t i = 0; i < colours.size(); ++i)
    colours[i] = Rgb8{static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(i * 7), static_cast<std::uint8_t>(i / 3)};
  map.setColours(colours);
  return map;
}

/// A terrestrial scanner in a room, a whole turn, its noise following the range, a few rays without return.
RangeMap roomAroundAScanner() {
  const int width = 121, height = 41;  // 3 degree steps, the first column again after the last
  const SphericalProjection grid{-M_PI, 2.0 * M_PI / 120.0, -60.0 * M_PI / 180.0, 3.0 * M_PI / 180.0};
  std::vector<float> ranges;
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const Vec3d d = sphericalDirection(grid, u % 120, v);
      const double wall = 2.0 / std::max(std::fabs(d.x()), std::max(std::fabs(d.y()), std::fabs(d.z())));
      ranges.push_back(u % 120 == 17 && v > 30 ? 0.0f : static_cast<float>(wall));
    }
  openvdb::math::Mat4d pose = openvdb::math::Mat4d::identity();
  pose.setToRotation(openvdb::math::Z_AXIS, 0.4);
  pose.setTranslation(Vec3d(1.0, -0.5, 1.5));
  return RangeMap::spherical(width, height, ranges, grid, pose, DepthNoise{0.002, 0.0, 0.001}, "room");
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Every reading, and what the map says at points around its readings, the same bit for bit.
void expectSameMap(const RangeMap& a, const RangeMap& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  ASSERT_EQ(a.validCount(), b.validCount());
  for (int v = 0; v < a.height(); ++v)
    for (int u = 0; u < a.width(); ++u) ASSERT_TRUE(sameBits(a.reading(u, v), b.reading(u, v))) << u << ", " << v;
  EXPECT_EQ(a.colours(), b.colours());
  ASSERT_EQ(a.samples().size(), b.samples().size());
  for (std::size_t i = 0; i < a.samples().size(); ++i) EXPECT_EQ(a.samples()[i], b.samples()[i]);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  int sampled = 0;
  for (int v = 1; v < a.height() - 1; ++v)
    for (int u = 1; u < a.width() - 1; ++u) {
      if (!a.valid(u, v)) continue;
      const Vec3d x = a.readingPoint(u, v) + Vec3d(jitter(random), jitter(random), jitter(random));
      RangeSample sa, sb;
      const bool hasA = a.sample(x, sa), hasB = b.sample(x, sb);
      ASSERT_EQ(hasA, hasB);
      if (hasA) {
        EXPECT_EQ(sa.D, sb.D);
        EXPECT_EQ(sa.sigma, sb.sigma);
        EXPECT_EQ(sa.gamma, sb.gamma);
        EXPECT_EQ(sa.gradD, sb.gradD);
        EXPECT_EQ(sa.lineOfSight, sb.lineOfSight);
        ++sampled;
      }
      EXPECT_EQ(a.sight(x, 0.01), b.sight(x, 0.01));
      // The usable cell at the pixel, and the reading bounds of the blocks over a window around it.
      EXPECT_EQ(a.cellUsable(u, v), b.cellUsable(u, v)) << u << ", " << v;
      double loA = 0.0, hiA = 0.0, loB = 0.0, hiB = 0.0;
      bool completeA = false, completeB = true;
      ASSERT_EQ(a.readingBounds(u - 3.5, v - 3.5, u + 3.5, v + 3.5, loA, hiA, &completeA),
                b.readingBounds(u - 3.5, v - 3.5, u + 3.5, v + 3.5, loB, hiB, &completeB));
      EXPECT_EQ(loA, loB);
      EXPECT_EQ(hiA, hiB);
      EXPECT_EQ(completeA, completeB);
    }
  EXPECT_GT(sampled, 500) << a.name();
}

/// The corner frame with one reading that is not a whole number of millimetres.
RangeMap cornerFrameOffStep() {
  RangeMap map = cornerFrame();
  std::vector<float> depths;
  for (int v = 0; v < map.height(); ++v)
    for (int u = 0; u < map.width(); ++u) depths.push_back(map.reading(u, v));
  depths[500] += 0.0004f;
  RangeMap off = RangeMap::pinhole(map.width(), map.height(), depths, map.pinholeProjection(), map.mapToWorld(),
                                   0.002, "corner, off step");
  off.setDepthNoise(DepthNoise{});
  off.setReadingStep(0.001);
  return off;
}

TEST(PackedRangeMap, UnpacksToTheMapItPacked) {
  for (const RangeMap& map : {cornerFrame(), cornerFrameOffStep(), everythingPerPixel(), roomAroundAScanner()}) {
    const PackedRangeMap packed{RangeMap(map)};
    expectSameMap(map, packed.unpack());
    expectSameMap(map, packed.unpack());  // as often as asked
  }
}

TEST(PackedRangeMap, SamplesLetGoAreCountedButNoLongerHeld) {
  // A map resampled from the points it measured, which only the fit reads.
  const RangeMap whole = everythingPerPixel();
  ASSERT_FALSE(whole.samples().empty());
  RangeMap without = whole;
  without.letSamplesGo();
  EXPECT_TRUE(without.samplesLetGo());
  EXPECT_TRUE(without.samples().empty());
  EXPECT_EQ(without.sampleCount(), whole.sampleCount());
  EXPECT_EQ(without.sampleCount(), whole.samples().size());
  // The data term and the sight are the map's.
  int sampled = 0;
  for (int v = 0; v < whole.height(); v += 3)
    for (int u = 0; u < whole.width(); u += 3) {
      if (!whole.valid(u, v)) continue;
      const Vec3d x = whole.readingPoint(u, v) + Vec3d(0.01, -0.02, 0.03);
      RangeSample a, b;
      ASSERT_EQ(whole.sample(x, a), without.sample(x, b));
      EXPECT_EQ(a.D, b.D);
      EXPECT_EQ(a.gradD, b.gradD);
      EXPECT_EQ(whole.sight(x, 0.01), without.sight(x, 0.01));
      sampled += 1;
    }
  EXPECT_GT(sampled, 50);
  // Packed: let go before or after packing, the map unpacks without them, counted.
  PackedRangeMap packed{RangeMap(whole)};
  const std::size_t bytes = packed.memoryBytes();
  packed.letSamplesGo();
  EXPECT_LT(packed.memoryBytes(), bytes);
  for (const RangeMap& unpacked : {packed.unpack(), PackedRangeMap(RangeMap(without)).unpack()}) {
    EXPECT_TRUE(unpacked.samplesLetGo());
    EXPECT_EQ(unpacked.sampleCount(), whole.sampleCount());
    expectSameMap(without, unpacked);
  }
  // A map whose readings are its samples has nothing to let go.
  RangeMap frame = cornerFrame();
  const std::size_t readings = frame.sampleCount();
  frame.letSamplesGo();
  EXPECT_FALSE(frame.samplesLetGo());
  EXPECT_EQ(frame.sampleCount(), readings);
}

TEST(PackedRangeMap, ReadingsAreHeldAsStepsOnlyWhenEveryOneIsExactlyThat) {
  EXPECT_TRUE(PackedRangeMap(cornerFrame()).readingsAsSteps());
  EXPECT_FALSE(PackedRangeMap(cornerFrameOffStep()).readingsAsSteps());
  EXPECT_FALSE(PackedRangeMap(everythingPerPixel()).readingsAsSteps());  // no step given
  RangeMap wrongStep = cornerFrame();
  wrongStep.setReadingStep(0.003);
  EXPECT_FALSE(PackedRangeMap(std::move(wrongStep)).readingsAsSteps());
  EXPECT_THROW(cornerFrame().setReadingStep(-0.001), std::invalid_argument);
}

TEST(PackedRangeMap, ADepthFrameTakesLessMemory) {
  // Readings of millimetre depths with 2 mm of white noise, held as 16-bit
  // steps; the map's per-pixel flags and block bounds are packed too.
  const RangeMap frame = cornerFrame();
  const PackedRangeMap packed{RangeMap(frame)};
  EXPECT_LT(packed.memoryBytes(), frame.memoryBytes() / 3)
      << packed.memoryBytes() << " bytes packed, " << frame.memoryBytes() << " unpacked";
  EXPECT_GT(frame.memoryBytes(), frame.validCount() * sizeof(float));  // the readings are counted
  // Without the step, as floats: more.
  EXPECT_GT(PackedRangeMap(cornerFrameOffStep()).memoryBytes(), packed.memoryBytes() * 3 / 2);
}

TEST(PackedRangeMap, ASevenScenesFrameTakesASeventhOfItsMemory) {
  const std::string folder = test::sharedData("7scenes-seq");
  if (folder.empty()) GTEST_SKIP() << "../shared/data is not beside the source tree";
  const RangeMap frame = io::depthFrame(io::readDepthPng(folder + "/frame-000000.depth.png"),
                                        io::readIntrinsics(folder + "/camera-intrinsics.txt"),
                                        io::readPose(folder + "/frame-000000.pose.txt"), io::DepthNoise{}, "frame 0");
  const PackedRangeMap packed{RangeMap(frame)};
  EXPECT_TRUE(packed.readingsAsSteps());
  EXPECT_LT(packed.memoryBytes(), frame.memoryBytes() / 7)
      << packed.memoryBytes() << " bytes packed, " << frame.memoryBytes() << " unpacked";
  expectSameMap(frame, packed.unpack());
}

}  // namespace
}  // namespace levelfuse
