// Synthetic range maps: exact renderings and stated noise.

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/synth/Scenes.h>
#include <levelfuse/synth/Synth.h>

#include <gtest/gtest.h>

#include <cmath>

namespace levelfuse::synth {
namespace {

using openvdb::Vec3d;

TEST(Synth, RenderedReadingsLieOnTheShape) {
  const shapes::Torus torus{Vec3d(0.1, -0.2, 0.05), 1.0, 0.35};
  for (const View& view : {orthographicView(Vec3d(0.3, -1.0, -0.5), Vec3d(0.0), 3.0, 120),
                           pinholeView(Vec3d(0.5, 3.0, 2.0), Vec3d(0.0), 50.0, 160, 120),
                           sphericalViewOf(Vec3d(0.5, 3.0, 2.0), Vec3d(0.0), 1.5, 120)}) {
    const RangeMap map = renderDistanceFunction(torus, view, Noise{}, 0.01);
    ASSERT_GT(map.validCount(), 2000u);
    double worst = 0.0;
    for (int v = 0; v < map.height(); ++v)
      for (int u = 0; u < map.width(); ++u)
        if (map.valid(u, v)) worst = std::max(worst, std::fabs(torus(map.readingPoint(u, v))));
    EXPECT_LT(worst, 1e-5);
  }
}

TEST(Synth, MeshesRenderLikeTheirDistanceFunction) {
  // A cube of half-size 0.5 as 12 triangles, and as a distance function.
  const std::vector<Vec3d> corners{{-.5, -.5, -.5}, {.5, -.5, -.5}, {.5, .5, -.5}, {-.5, .5, -.5},
                                   {-.5, -.5, .5},  {.5, -.5, .5},  {.5, .5, .5},  {-.5, .5, .5}};
  const std::vector<openvdb::Vec3I> triangles{{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                              {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  const shapes::Box box{Vec3d(0.0), Vec3d(0.5)};
  for (const View& view : {orthographicView(Vec3d(-0.4, -0.7, -1.0), Vec3d(0.0), 2.0, 80),
                           pinholeView(Vec3d(2.0, 1.5, 1.0), Vec3d(0.0), 45.0, 80, 60),
                           sphericalViewOf(Vec3d(2.0, 1.5, 1.0), Vec3d(0.0), 0.9, 80),
                           sphericalView(Vec3d(0.05, 0.1, -0.02), -180.0, 180.0, -60.0, 60.0, 3.0)}) {
    // Seen from inside the cube (a whole turn), its inside is the free space.
    const bool inside = box(view.mapToWorld.transform(Vec3d(0.0))) < 0.0;
    const RangeMap fromMesh = renderMesh(corners, triangles, view, Noise{}, 0.01);
    const RangeMap fromDistance =
        renderDistanceFunction([&](const Vec3d& p) { return inside ? -box(p) : box(p); }, view, Noise{}, 0.01);
    std::size_t compared = 0;
    for (int v = 0; v < view.height; ++v)
      for (int u = 0; u < view.width; ++u) {
        if (!fromMesh.valid(u, v) || !fromDistance.valid(u, v)) continue;
        EXPECT_NEAR(fromMesh.reading(u, v), fromDistance.reading(u, v), 1e-5) << u << "," << v;
        ++compared;
      }
    EXPECT_GT(compared, 800u);
    // Silhouettes agree to a pixel or so.
    EXPECT_NEAR(double(fromMesh.validCount()), double(fromDistance.validCount()), 0.05 * fromMesh.validCount());
  }
}

TEST(Synth, NoiseHasTheStatedSize) {
  const shapes::Sphere sphere{Vec3d(0.0), 1.0};
  const View view = orthographicView(Vec3d(0, 0, -1), Vec3d(0.0), 2.2, 200);
  const RangeMap clean = renderDistanceFunction(sphere, view, Noise{}, 0.01);
  Noise gaussian;
  gaussian.gaussianSigma = 0.02;
  gaussian.seed = 7;
  const RangeMap noisy = renderDistanceFunction(sphere, view, gaussian, 0.02);
  double sum = 0.0, sumSq = 0.0;
  std::size_t n = 0;
  for (int v = 0; v < 200; ++v)
    for (int u = 0; u < 200; ++u)
      if (clean.valid(u, v)) {
        const double e = noisy.reading(u, v) - clean.reading(u, v);
        sum += e;
        sumSq += e * e;
        ++n;
      }
  EXPECT_NEAR(sum / n, 0.0, 0.001);
  EXPECT_NEAR(std::sqrt(sumSq / n), 0.02, 0.0005);

  Noise outliers;
  outliers.replacementFraction = 0.05;
  const RangeMap replaced = renderDistanceFunction(sphere, view, outliers, 0.01);
  std::size_t moved = 0;
  for (int v = 0; v < 200; ++v)
    for (int u = 0; u < 200; ++u)
      if (clean.valid(u, v) && std::fabs(replaced.reading(u, v) - clean.reading(u, v)) > 1e-6) ++moved;
  EXPECT_NEAR(double(moved) / n, 0.05, 0.006);
  // The same seed gives the same noise.
  const RangeMap again = renderDistanceFunction(sphere, view, gaussian, 0.02);
  EXPECT_EQ(again.reading(100, 100), noisy.reading(100, 100));
}

TEST(Synth, ViewsSurroundTheObject) {
  const auto six = sixAxisViews(Vec3d(1.0, 2.0, 3.0), 2.0, 50);
  ASSERT_EQ(six.size(), 6u);
  const auto around = viewsAround(Vec3d(0.0), 2.0, 50, 10);
  ASSERT_EQ(around.size(), 10u);
  Vec3d mean(0.0);
  for (const View& v : around) mean += v.mapToWorld.transform3x3(Vec3d(0, 0, 1));
  EXPECT_LT(mean.length() / 10.0, 0.1);  // spread evenly: directions nearly cancel
}

TEST(Synth, TheRoomIsScannedFromThreeTripods) {
  const shapes::Room room;
  SceneOptions options;
  options.resolution = 60;  // 1.5 degree steps
  const Scene clean = roomScene(room, options);
  options.noise = 0.0004;  // of the room's height at 1 m: 1 mm per metre of range
  const Scene noisy = roomScene(room, options);
  ASSERT_EQ(noisy.maps.size(), 3u);
  ASSERT_TRUE(noisy.truth);
  EXPECT_STREQ(noisy.truth->name(), "room");
  for (std::size_t i = 0; i < noisy.maps.size(); ++i) {
    const RangeMap& exact = clean.maps[i];
    const RangeMap& map = noisy.maps[i];
    EXPECT_EQ(map.kind(), RangeMap::Kind::kSpherical);
    EXPECT_EQ(map.width(), 241);  // a whole turn, its first column again after its last
    EXPECT_EQ(map.height(), 101);
    EXPECT_EQ(map.validCount(), 241u * 101u);  // a closed room: every ray returns
    ASSERT_NE(map.depthNoise(), nullptr);
    EXPECT_NEAR(map.depthNoise()->perMetre, 0.001, 1e-12);
    double worst = 0.0, sum = 0.0, sumOfSquares = 0.0;
    for (int v = 0; v < map.height(); ++v)
      for (int u = 0; u < map.width(); ++u) {
        worst = std::max(worst, std::fabs(room(exact.readingPoint(u, v))));
        const double error = (map.reading(u, v) - exact.reading(u, v)) / exact.reading(u, v);  // per metre of range
        sum += error;
        sumOfSquares += error * error;
      }
    EXPECT_LT(worst, 1e-5) << map.name();
    const double n = double(map.validCount());
    EXPECT_NEAR(std::sqrt(sumOfSquares / n - (sum / n) * (sum / n)), 0.001, 0.0001) << map.name();
  }
}

}  // namespace
}  // namespace levelfuse::synth
