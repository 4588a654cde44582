// Results are bit-identical whatever the number of threads.

#include "support/TestSupport.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/levelset/LevelSetFromFunction.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <cmath>

namespace levelfuse {
namespace {

openvdb::FloatGrid::Ptr evolve(std::size_t threads, std::size_t grain) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  const shapes::Dumbbell dumbbell{openvdb::Vec3d(0.1, 0.2, -0.1), 9.0, 24.0, 3.5};
  SparseField field = SparseField::fromLevelSet(
      *levelSetFromFunction(dumbbell, openvdb::BBoxd(openvdb::Vec3d(-26, -14, -14), openvdb::Vec3d(26, 14, 14)), 1.0));
  field.setGrainSize(grain);
  const ExternalForceSpeed speed{[](const openvdb::Vec3d& x, const openvdb::Vec3d& n) {
                                   return 0.6 * std::sin(0.3 * x.x()) + 0.4 * std::cos(0.2 * x.y() + 0.1 * x.z()) +
                                          0.1 * n.z();
                                 },
                                 0.8, ForceSampling::kSubcell};
  for (int i = 0; i < 60; ++i) field.step(speed);
  return field.toLevelSet(3.0);
}

TEST(Determinism, OneAndTwoThreadsGiveIdenticalResults) {
  const auto serial = evolve(1, 0);
  const auto one = evolve(1, 1);
  const auto two = evolve(2, 1);
  const auto coarse = evolve(2, 16);
  std::string why;
  EXPECT_TRUE(test::identical(*serial, *one, &why)) << why;
  EXPECT_TRUE(test::identical(*one, *two, &why)) << why;
  EXPECT_TRUE(test::identical(*two, *coarse, &why)) << why;
}

TEST(Determinism, RepeatedRunsAreIdentical) {
  const auto a = evolve(2, 1);
  const auto b = evolve(2, 1);
  std::string why;
  EXPECT_TRUE(test::identical(*a, *b, &why)) << why;
}

}  // namespace
}  // namespace levelfuse
