// Distances to a level set's zero set from points beyond its band, found in
// growing cubes around them.

#include "../../src/recon/ZeroSetDistance.h"

#include "support/TestSupport.h"

#include <openvdb/tools/LevelSetSphere.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

constexpr double kStep = 0.02;  // voxel size (m)

openvdb::FloatGrid::Ptr unitSphere() {
  return openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(0.0f), float(kStep), 3.0f);
}

TEST(ZeroSetDistance, FindsTheSurfaceNearOrFar) {
  // From 4 voxels to 200 voxels away, inside and outside, a point at a time:
  // the first cube, a doubled one, and the whole zero set.
  const auto sphere = unitSphere();
  for (const double offset : {0.08, -0.3, 0.5, -0.9, 1.5, 4.0})
    for (const Vec3d& p : test::pointsOnSphere(Vec3d(0.0), 1.0 + offset, 10, 3)) {
      const std::vector<double> distance = detail::distancesToZeroSet(*sphere, {p});
      ASSERT_EQ(distance.size(), 1u);
      // Within the cubes (to 64 voxels), the mesh's triangles; beyond, its
      // nearest vertex, found by ClosestSurfacePoint within a thousandth.
      const double tolerance = std::fabs(offset) < 1.28 ? 0.02 * kStep : 1e-3 * std::fabs(offset);
      EXPECT_NEAR(distance[0], std::fabs(offset), tolerance) << offset;
    }
}

TEST(ZeroSetDistance, ManyPointsAreMeasuredToTheWholeZeroSetOnce) {
  // More points than cubes the band could hold: the nearest vertex of the
  // whole zero set's mesh, a voxel or so apart, so a little farther.
  const auto sphere = unitSphere();
  const std::vector<Vec3d> points = test::pointsOnSphere(Vec3d(0.0), 1.08, 400, 5);
  const std::vector<double> distance = detail::distancesToZeroSet(*sphere, points);
  ASSERT_EQ(distance.size(), points.size());
  for (double d : distance) {
    EXPECT_GE(d, 0.08 - 0.02 * kStep);
    EXPECT_LE(d, 0.08 + 0.1 * kStep);
  }
}

TEST(ZeroSetDistance, GivesEachPointItsOwnNearestSurface) {
  // Two spheres far apart: each point's distance is to the sphere beside it,
  // whichever cube found it (the smaller sphere's facets lie up to 0.03
  // voxels inside it).
  auto spheres = unitSphere();
  const auto other = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(0.5f, openvdb::Vec3f(6.0f, 0.0f, 0.0f),
                                                                             float(kStep), 3.0f);
  spheres->tree().combineExtended(other->tree(), [](openvdb::CombineArgs<float>& a) {
    a.setResult(std::min(a.a(), a.b()));
    a.setResultIsActive(a.aIsActive() || a.bIsActive());
  });
  const std::vector<Vec3d> points{Vec3d(1.2, 0.0, 0.0), Vec3d(6.0, 0.0, 0.9), Vec3d(3.0, 0.0, 0.0),
                                  Vec3d(6.0, 0.0, 0.0)};
  const std::vector<double> distance = detail::distancesToZeroSet(*spheres, points);
  EXPECT_NEAR(distance[0], 0.2, 0.05 * kStep);
  EXPECT_NEAR(distance[1], 0.4, 0.05 * kStep);
  EXPECT_NEAR(distance[2], 2.0, 0.05 * kStep);
  EXPECT_NEAR(distance[3], 0.5, 0.05 * kStep);
}

TEST(ZeroSetDistance, IsInfiniteWithoutAZeroSet) {
  openvdb::FloatGrid empty(float(3.0 * kStep));
  empty.setTransform(openvdb::math::Transform::createLinearTransform(kStep));
  empty.setGridClass(openvdb::GRID_LEVEL_SET);
  const std::vector<double> distance = detail::distancesToZeroSet(empty, {Vec3d(0.0), Vec3d(1.0, 2.0, 3.0)});
  ASSERT_EQ(distance.size(), 2u);
  EXPECT_TRUE(std::isinf(distance[0]));
  EXPECT_TRUE(std::isinf(distance[1]));
  EXPECT_TRUE(detail::distancesToZeroSet(*unitSphere(), {}).empty());
}

}  // namespace
}  // namespace levelfuse
