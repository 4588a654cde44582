// Exact distances from points to triangles and to a mesh.

#include <levelfuse/geometry/NearestTriangle.h>
#include <levelfuse/levelset/Mesh.h>

#include <openvdb/tools/LevelSetSphere.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

TEST(PointTriangleDistance, EveryRegionOfTheTriangle) {
  // The right triangle (0,0,0), (1,0,0), (0,1,0) in the plane z = 0.
  const Vec3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const auto d = [&](double x, double y, double z) { return pointTriangleDistance(Vec3d(x, y, z), a, b, c); };
  EXPECT_NEAR(d(0.2, 0.3, 0.0), 0.0, 1e-15);          // inside
  EXPECT_DOUBLE_EQ(d(0.2, 0.3, -0.7), 0.7);           // over the face, either side
  EXPECT_DOUBLE_EQ(d(-1.0, -1.0, 0.0), std::sqrt(2.0));  // vertex a
  EXPECT_DOUBLE_EQ(d(2.0, 0.0, 1.0), std::sqrt(2.0));    // vertex b
  EXPECT_DOUBLE_EQ(d(0.0, 3.0, 0.0), 2.0);               // vertex c
  EXPECT_DOUBLE_EQ(d(0.5, -2.0, 0.0), 2.0);              // edge ab
  EXPECT_DOUBLE_EQ(d(-0.5, 0.5, 0.0), 0.5);              // edge ca
  EXPECT_NEAR(d(1.0, 1.0, 0.0), std::sqrt(0.5), 1e-15);  // edge bc
  // Degenerate triangles: a segment and a point.
  EXPECT_DOUBLE_EQ(pointTriangleDistance(Vec3d(0.5, 1.0, 0.0), a, b, Vec3d(0.5, 0, 0)), 1.0);
  EXPECT_DOUBLE_EQ(pointTriangleDistance(Vec3d(0.0, 0.0, 2.0), a, a, a), 2.0);
}

/// The zero set of a sphere of radius 1 as a mesh of about 40,000 triangles.
TriangleMesh sphereMesh() {
  return meshFromLevelSet(*openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(0.1f), 0.03f));
}

TEST(NearestTriangle, AgreesWithEveryTriangleMeasured) {
  const TriangleMesh mesh = sphereMesh();
  ASSERT_GT(mesh.triangleCount(), 10000u);
  const NearestTriangle nearest(mesh.xyz, mesh.triangles);
  const auto bruteForce = [&](const Vec3d& p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      const auto v = [&](int k) {
        const std::uint32_t i = mesh.triangles[3 * t + k];
        return Vec3d(mesh.xyz[3 * i], mesh.xyz[3 * i + 1], mesh.xyz[3 * i + 2]);
      };
      best = std::min(best, pointTriangleDistance(p, v(0), v(1), v(2)));
    }
    return best;
  };
  std::mt19937 random(17);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> radius(0.0, 3.0);  // from the centre to two radii out
  for (int i = 0; i < 300; ++i) {
    Vec3d direction(normal(random), normal(random), normal(random));
    direction.normalize();
    const Vec3d p = Vec3d(0.1) + direction * radius(random);
    EXPECT_EQ(nearest.distance(p), bruteForce(p)) << p;
  }
  // Beyond the rings of cells a query visits (8 cells, about 0.4 here): the tree of cells.
  std::uniform_real_distribution<double> far(1.5, 60.0);
  for (int i = 0; i < 100; ++i) {
    Vec3d direction(normal(random), normal(random), normal(random));
    direction.normalize();
    const Vec3d p = Vec3d(0.1) + direction * far(random);
    EXPECT_EQ(nearest.distance(p), bruteForce(p)) << p;
  }
  // Far beyond the cells a query visits, and beyond any cell address.
  for (const Vec3d& p : {Vec3d(40.0, -3.0, 2.0), Vec3d(1e12, 0.0, 0.0)}) EXPECT_EQ(nearest.distance(p), bruteForce(p)) << p;
}

TEST(NearestTriangle, MeasuresTrianglesLargerThanItsCells) {
  // Many small triangles set the cells; one huge triangle spans thousands of them.
  std::vector<float> xyz;
  std::vector<std::uint32_t> triangles;
  for (int i = 0; i < 100; ++i) {
    const float x = 0.01f * static_cast<float>(i);
    const std::uint32_t base = static_cast<std::uint32_t>(xyz.size() / 3);
    xyz.insert(xyz.end(), {x, 0.f, 0.f, x + 0.01f, 0.f, 0.f, x, 0.01f, 0.f});
    triangles.insert(triangles.end(), {base, base + 1, base + 2});
  }
  const std::uint32_t base = static_cast<std::uint32_t>(xyz.size() / 3);
  xyz.insert(xyz.end(), {-50.f, -50.f, 5.f, 50.f, -50.f, 5.f, 0.f, 50.f, 5.f});
  triangles.insert(triangles.end(), {base, base + 1, base + 2});
  const NearestTriangle nearest(xyz, triangles);
  EXPECT_NEAR(nearest.distance(Vec3d(20.0, 0.0, 5.5)), 0.5, 1e-6);
  EXPECT_NEAR(nearest.distance(Vec3d(0.5, 0.005, 0.1)), 0.1, 1e-6);
}

TEST(NearestTriangle, RefusesMeshesItCannotMeasure) {
  const std::vector<float> xyz{0, 0, 0, 1, 0, 0, 0, 1, 0};
  EXPECT_THROW(NearestTriangle(xyz, {}), std::invalid_argument);
  EXPECT_THROW(NearestTriangle(xyz, {0, 1, 3}), std::invalid_argument);
  EXPECT_THROW(NearestTriangle(xyz, {0, 1}), std::invalid_argument);
  const std::vector<float> bad{0, 0, 0, 1, NAN, 0, 0, 1, 0};
  EXPECT_THROW(NearestTriangle(bad, {0, 1, 2}), std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse
