// Topology changes: merging, splitting and vanishing components just work.

#include "support/TestSupport.h"

#include <levelfuse/levelset/Components.h>

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/levelset/Invariants.h>
#include <levelfuse/levelset/LevelSetFromFunction.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>

#include <gtest/gtest.h>

namespace levelfuse {
namespace {

TEST(Topology, TwoGrowingSpheresMerge) {
  const auto twoSpheres = [](const openvdb::Vec3d& p) {
    return std::min(shapes::Sphere{openvdb::Vec3d(-10.2, 0.1, 0.0), 8.0}(p),
                    shapes::Sphere{openvdb::Vec3d(10.1, -0.2, 0.3), 8.0}(p));
  };
  SparseField field = SparseField::fromLevelSet(
      *levelSetFromFunction(twoSpheres, openvdb::BBoxd(openvdb::Vec3d(-22), openvdb::Vec3d(22)), 1.0));
  ASSERT_EQ(insideComponents(field.grid()), 2);
  field.advance(ConstantSpeed{ConstantForce{1.0}}, 4.0, [&] {
    EXPECT_TRUE(checkInvariants(field).ok());
    return false;
  });
  EXPECT_EQ(insideComponents(field.grid()), 1);
  // The bridge is solid: the midpoint lies well inside.
  EXPECT_LT(field.grid().tree().getValue(openvdb::Coord(0, 0, 0)), 0.0f);
}

TEST(Topology, DumbbellPinchesUnderCurvatureFlow) {
  const shapes::Dumbbell dumbbell{openvdb::Vec3d(0.1, 0.2, -0.1), 10.0, 28.0, 3.0};
  SparseField field = SparseField::fromLevelSet(
      *levelSetFromFunction(dumbbell, openvdb::BBoxd(openvdb::Vec3d(-30, -15, -15), openvdb::Vec3d(30, 15, 15)), 1.0));
  ASSERT_EQ(insideComponents(field.grid()), 1);
  // The bar (radius 3) pinches near t = 4.5, at both ends, and the piece left
  // between collapses; the spheres (radius 10) survive.
  std::size_t steps = field.advance(MeanCurvatureFlow{1.0}, 8.0, [&] {
    const InvariantReport report = checkInvariants(field);
    EXPECT_TRUE(report.ok()) << report.firstViolation;
    return !report.ok();
  });
  EXPECT_GT(steps, 25u);
  EXPECT_EQ(insideComponents(field.grid()), 2);
  EXPECT_GT(field.grid().tree().getValue(openvdb::Coord(0, 0, 0)), 0.0f);
  EXPECT_LT(field.grid().tree().getValue(openvdb::Coord(14, 0, 0)), 0.0f);
  EXPECT_LT(field.grid().tree().getValue(openvdb::Coord(-14, 0, 0)), 0.0f);
}

TEST(Topology, ATorusHoleClosesWhenTheTubeGrows) {
  const shapes::Torus torus{openvdb::Vec3d(0.2), 10.0, 4.0};
  SparseField field = SparseField::fromLevelSet(
      *levelSetFromFunction(torus, openvdb::BBoxd(openvdb::Vec3d(-16, -16, -6), openvdb::Vec3d(16, 16, 6)), 1.0));
  EXPECT_GT(field.grid().tree().getValue(openvdb::Coord(0, 0, 0)), 0.0f);
  field.advance(ConstantSpeed{ConstantForce{1.0}}, 7.0, [&] {
    EXPECT_TRUE(checkInvariants(field).ok());
    return false;
  });
  EXPECT_LT(field.grid().tree().getValue(openvdb::Coord(0, 0, 0)), 0.0f);
}

}  // namespace
}  // namespace levelfuse
