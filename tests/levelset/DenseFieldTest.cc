// The dense-field reference.

#include "support/TestSupport.h"

#include <levelfuse/levelset/DenseField.h>
#include <levelfuse/levelset/SpeedTerms.h>

#include <gtest/gtest.h>

namespace levelfuse {
namespace {

TEST(DenseField, SamplesALevelSetAndExportsIt) {
  const auto sphere = test::makeSphere(6.0);
  const DenseField dense = DenseField::fromLevelSet(*sphere, openvdb::CoordBBox(openvdb::Coord(-10), openvdb::Coord(10)));
  EXPECT_FLOAT_EQ(dense.value(openvdb::Coord(6, 0, 0)), sphere->tree().getValue(openvdb::Coord(6, 0, 0)));
  EXPECT_FLOAT_EQ(dense.value(openvdb::Coord(0, 0, 0)), -3.0f);
  const auto grid = dense.toGrid(3.0);
  EXPECT_NEAR(test::fitRadius(*grid, openvdb::Vec3d(0.0)).mean, 6.0, 0.05);
  EXPECT_LT(grid->tree().getValue(openvdb::Coord(0)), 0.0f);
  EXPECT_EQ(dense.memoryBytes(), 2u * 21 * 21 * 21 * sizeof(float));
}

TEST(DenseField, GrowsAtConstantSpeed) {
  // 12 voxels growing to 16: the first-order up-wind scheme lags by O(h/R).
  DenseField dense(openvdb::CoordBBox(openvdb::Coord(-24), openvdb::Coord(24)),
                   openvdb::math::Transform::createLinearTransform(0.25),
                   [](const openvdb::Vec3d& p) { return p.length() - 3.0; });
  double t = 0.0;
  for (int i = 0; i < 10; ++i) t += dense.step(ConstantSpeed{ConstantForce{1.0}}, 0.1).dt;
  EXPECT_DOUBLE_EQ(t, 1.0);
  EXPECT_NEAR(test::fitRadius(*dense.toGrid(), openvdb::Vec3d(0.0)).mean, 4.0, 0.25 * 0.15);
}

TEST(DenseField, RejectsAnEmptyBox) {
  EXPECT_THROW(DenseField(openvdb::CoordBBox(), openvdb::math::Transform::createLinearTransform(1.0),
                          [](const openvdb::Vec3d&) { return 0.0; }),
               std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse
