// Triangles rasterised along the line of sight, with and without the edge extension.

#include <levelfuse/scan/DepthRaster.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;
using openvdb::Vec3I;

/// The plane z = 1 + 0.1 u - 0.2 v at pixel (u, v).
double plane(double u, double v) { return 1.0 + 0.1 * u - 0.2 * v; }

/// A right triangle of the plane with its corners at pixel coordinates
/// (2.3, 2.6), (7.4, 2.6), (2.3, 6.8): not on pixel centres.
std::vector<Vec3d> triangleCorners() {
  return {Vec3d(2.3, 2.6, plane(2.3, 2.6)), Vec3d(7.4, 2.6, plane(7.4, 2.6)), Vec3d(2.3, 6.8, plane(2.3, 6.8))};
}

bool inside(int x, int y) { return x >= 2.3 && y >= 2.6 && (x - 2.3) / 5.1 + (y - 2.6) / 4.2 <= 1.0; }

TEST(DepthRaster, PixelCentresInsideATriangleTakeItsPlane) {
  const std::vector<float> depth = rasteriseDepth(triangleCorners(), {Vec3I(0, 1, 2)}, 12, 10);
  int covered = 0;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 12; ++x) {
      const float d = depth[y * 12 + x];
      if (inside(x, y)) {
        EXPECT_NEAR(d, plane(x, y), 1e-6) << x << ", " << y;
        ++covered;
      } else {
        EXPECT_TRUE(std::isnan(d)) << x << ", " << y;
      }
    }
  EXPECT_EQ(covered, 10);  // rows 3 to 6 hold 4, 3, 2 and 1 pixel centres inside
}

TEST(DepthRaster, TheEdgeExtensionExtrapolatesThePlaneAShortWayOnly) {
  const double extension = 1.5;
  const std::vector<float> depth = rasteriseDepth(triangleCorners(), {Vec3I(0, 1, 2)}, 12, 10, extension);
  const auto distanceToTriangle = [](double x, double y) {
    // Outside the right triangle: the nearest of its three edges.
    const auto segment = [&](double ax, double ay, double bx, double by) {
      const double dx = bx - ax, dy = by - ay;
      double t = ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy);
      t = std::fmin(1.0, std::fmax(0.0, t));
      return std::hypot(ax + t * dx - x, ay + t * dy - y);
    };
    return std::fmin(segment(2.3, 2.6, 7.4, 2.6), std::fmin(segment(7.4, 2.6, 2.3, 6.8), segment(2.3, 6.8, 2.3, 2.6)));
  };
  int extended = 0;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 12; ++x) {
      const float d = depth[y * 12 + x];
      if (inside(x, y) || distanceToTriangle(x, y) <= extension) {
        EXPECT_NEAR(d, plane(x, y), 1e-5) << x << ", " << y;  // a plane extrapolates exactly
        extended += !inside(x, y);
      } else {
        EXPECT_TRUE(std::isnan(d)) << x << ", " << y;
      }
    }
  EXPECT_GT(extended, 10);
  // Every corner now lies in a cell of four readings: bilinear interpolation reaches it.
  for (const Vec3d& c : triangleCorners()) {
    const int i = static_cast<int>(c.x()), j = static_cast<int>(c.y());
    for (int k = 0; k < 4; ++k) EXPECT_FALSE(std::isnan(depth[(j + k / 2) * 12 + i + k % 2])) << c;
  }
}

TEST(DepthRaster, TheNearestSurfaceWinsAndExtensionsNeverCoverIt) {
  // Two squares of two triangles each over rows -0.5 to 6.5: a far one at
  // depth 5 over u = -0.5 to 4.5 and a near one at depth 2 over u = 2.5 to
  // 7.5. The near one wins where they overlap; the far one's extension must
  // not reach past it, the near one's reaches 1.5 pixels.
  std::vector<Vec3d> v = {Vec3d(-0.5, -0.5, 5), Vec3d(4.5, -0.5, 5), Vec3d(-0.5, 6.5, 5), Vec3d(4.5, 6.5, 5),
                          Vec3d(2.5, -0.5, 2),  Vec3d(7.5, -0.5, 2), Vec3d(2.5, 6.5, 2),  Vec3d(7.5, 6.5, 2)};
  const std::vector<Vec3I> t = {Vec3I(0, 1, 2), Vec3I(1, 3, 2), Vec3I(4, 5, 6), Vec3I(5, 7, 6)};
  const std::vector<float> depth = rasteriseDepth(v, t, 12, 7, 1.5);
  for (int y = 0; y <= 6; ++y) {
    for (int x = 0; x <= 2; ++x) EXPECT_EQ(depth[y * 12 + x], 5.0f) << x << ", " << y;
    for (int x = 3; x <= 9; ++x) EXPECT_EQ(depth[y * 12 + x], 2.0f) << x << ", " << y;
    for (int x = 10; x <= 11; ++x) EXPECT_TRUE(std::isnan(depth[y * 12 + x])) << x << ", " << y;
  }
}

TEST(DepthRaster, RefusesBadArguments) {
  EXPECT_THROW(rasteriseDepth(triangleCorners(), {Vec3I(0, 1, 3)}, 12, 10), std::invalid_argument);
  EXPECT_THROW(rasteriseDepth(triangleCorners(), {Vec3I(0, 1, 2)}, 0, 10), std::invalid_argument);
  EXPECT_THROW(rasteriseDepth(triangleCorners(), {Vec3I(0, 1, 2)}, 12, 10, -1.0), std::invalid_argument);
  EXPECT_THROW(rasteriseDepth(triangleCorners(), {Vec3I(0, 1, 2)}, 12, 10, NAN), std::invalid_argument);
  // Edge-on triangles cover nothing.
  const std::vector<Vec3d> line = {Vec3d(1, 1, 1), Vec3d(5, 1, 1), Vec3d(9, 1, 1)};
  for (float d : rasteriseDepth(line, {Vec3I(0, 1, 2)}, 12, 3, 1.5)) EXPECT_TRUE(std::isnan(d));
}

}  // namespace
}  // namespace levelfuse
