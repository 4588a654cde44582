// The projections of range maps: for each kind, a point's pixel and that
// pixel's ray agree, and the points a kind cannot project are refused.

#include <levelfuse/scan/MapProjection.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;
using Vec2d = openvdb::math::Vec2d;

constexpr double kRadiansPerDegree = M_PI / 180.0;

MapProjection parallel() { return MapProjection(OrthographicProjection{0.25, Vec2d(-3.0, 2.0)}); }
MapProjection camera() { return MapProjection(PinholeProjection{525.0, 530.0, 319.5, 239.5}); }
MapProjection evenGrid() {
  return MapProjection(SphericalProjection(-60.0 * kRadiansPerDegree, 0.5 * kRadiansPerDegree, -30.0 * kRadiansPerDegree, 0.5 * kRadiansPerDegree));
}
MapProjection unevenGrid() {
  SphericalProjection p(10.0 * kRadiansPerDegree, -0.2 * kRadiansPerDegree, 0.0, 0.0);
  p.rowElevations = {-25.0 * kRadiansPerDegree, -10.0 * kRadiansPerDegree, -2.0 * kRadiansPerDegree, 3.0 * kRadiansPerDegree, 15.0 * kRadiansPerDegree};
  return MapProjection(p);
}

/// What `projection` says of its kind.
void expectKind(const MapProjection& projection, MapProjection::Kind kind, bool fromOneCentre, bool straight,
                const char* name) {
  EXPECT_EQ(projection.kind(), kind);
  EXPECT_EQ(projection.raysFromOneCentre(), fromOneCentre);
  EXPECT_EQ(projection.keepsLinesStraight(), straight);
  EXPECT_STREQ(projectionName(projection.kind()), name);
}

/// The point `projection` sees at pixel (u, v) with reading r lies on the
/// pixel's ray, projects back to (u, v) and reads r.
void expectRoundTrip(const MapProjection& projection, double u, double v, double r) {
  const Vec3d p = projection.pointAt(u, v, r);
  ASSERT_TRUE(projection.canProject(p)) << p;
  const Vec2d uv = projection.pixelOf(p);
  EXPECT_NEAR(uv.x(), u, 1e-9) << p;
  EXPECT_NEAR(uv.y(), v, 1e-9) << p;
  EXPECT_NEAR(projection.readingOf(p), r, 1e-9 * std::fabs(r) + 1e-12);
  const PixelRay ray = projection.rayOf(u, v);
  EXPECT_NEAR(ray.direction.length(), 1.0, 1e-12);
  const double t = (p - ray.origin).dot(ray.direction);
  EXPECT_NEAR((ray.origin + ray.direction * t - p).length(), 0.0, 1e-9 * (1.0 + std::fabs(r)));
  EXPECT_NEAR(projection.readingAlong(u, v, t), r, 1e-9 * std::fabs(r) + 1e-12);
  // The ray runs away from the scanner: farther readings lie farther along it.
  const double farther = (projection.pointAt(u, v, r + 1.0) - ray.origin).dot(ray.direction);
  EXPECT_GT(farther, t);
}

TEST(MapProjection, ParallelRaysRoundTrip) {
  const MapProjection p = parallel();
  expectKind(p, MapProjection::Kind::kOrthographic, false, true, "orthographic");
  for (const double r : {-2.0, 0.0, 3.5}) expectRoundTrip(p, 7.25, 11.5, r);
  EXPECT_NEAR((p.rayOf(4.0, 8.0).origin - Vec3d(-2.0, 4.0, 0.0)).length(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(p.raySpacingAt(100.0), 0.25);
}

TEST(MapProjection, PinholeRoundTrip) {
  const MapProjection p = camera();
  expectKind(p, MapProjection::Kind::kPinhole, true, true, "pinhole");
  for (const double u : {0.0, 319.5, 612.25})
    for (const double v : {3.0, 400.75}) expectRoundTrip(p, u, v, 2.5);
  // The principal point's ray is the optical axis; depth and distance agree there.
  EXPECT_NEAR((p.rayOf(319.5, 239.5).direction - Vec3d(0, 0, 1)).length(), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(p.raySpacingAt(5.25), 5.25 / 525.0);
}

TEST(MapProjection, PinholeRefusesPointsNotInFront) {
  const MapProjection p = camera();
  EXPECT_FALSE(p.canProject(Vec3d(0.1, 0.2, 0.0)));
  EXPECT_FALSE(p.canProject(Vec3d(0.1, 0.2, -1.0)));
  EXPECT_TRUE(p.canProject(Vec3d(0.1, 0.2, 1e-9)));
  EXPECT_GT(p.nearestReading(-1.0, 10.0), 0.0);
}

TEST(MapProjection, SphericalRoundTrip) {
  for (const MapProjection& p : {evenGrid(), unevenGrid()}) {
    expectKind(p, MapProjection::Kind::kSpherical, true, false, "spherical");
    for (const double u : {0.5, 17.5, 200.25})
      for (const double v : {0.0, 1.5, 3.75}) expectRoundTrip(p, u, v, 12.0);
    EXPECT_NEAR(p.azimuthPeriod(), 2.0 * M_PI / std::fabs(p.spherical().azimuthStep), 1e-9);
  }
}

TEST(MapProjection, SphericalRefusesPointsOnTheAxis) {
  const MapProjection p = evenGrid();
  EXPECT_FALSE(p.canProject(Vec3d(0.0, 0.0, 2.0)));
  EXPECT_FALSE(p.canProject(Vec3d(0.0, 0.0, -2.0)));
  EXPECT_TRUE(p.canProject(Vec3d(1e-6, 0.0, 2.0)));
  // Behind the scanner is still in view: a station sees all round.
  EXPECT_TRUE(p.canProject(Vec3d(-3.0, 0.5, 0.0)));
  EXPECT_DOUBLE_EQ(p.nearestReading(-1.0, 10.0), 0.0);
}

TEST(MapProjection, VisitsTheKindsOwnRays) {
  EXPECT_EQ(parallel().visit([](const auto& rays) { return rays.raySpacingAt(1.0); }), 0.25);
  const MapProjection p = camera();
  const Vec3d x(0.3, -0.2, 2.0);
  EXPECT_EQ(p.visit([&](const auto& rays) { return rays.pixelOf(x); }), p.pinholeRays().pixelOf(x));
}

TEST(MapProjection, OfKindTakesThatKindsParameters) {
  const OrthographicProjection o{0.5, Vec2d(1.0, 2.0)};
  const PinholeProjection k{300.0, 310.0, 100.0, 90.0};
  const SphericalProjection s(0.0, 0.01, -0.2, 0.01);
  EXPECT_EQ(MapProjection::ofKind(MapProjection::Kind::kOrthographic, o, k, s).orthographic().pixelSize, 0.5);
  EXPECT_EQ(MapProjection::ofKind(MapProjection::Kind::kPinhole, o, k, s).pinhole().fy, 310.0);
  EXPECT_EQ(MapProjection::ofKind(MapProjection::Kind::kSpherical, o, k, s).spherical().azimuthStep, 0.01);
}

}  // namespace
}  // namespace levelfuse
