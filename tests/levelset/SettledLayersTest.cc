// A step keeps the layers of the leaves its changes do not reach
// (SparseFieldOptions::keepSettledLayers): the same field as rebuilding
// every leaf's layers, bit for bit.

#include "support/TestSupport.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/levelset/Invariants.h>
#include <levelfuse/levelset/LevelSetFromFunction.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace levelfuse {
namespace {

/// The values and band of a dumbbell after `steps` steps of a push that moves
/// its surface only where x > 0 (outward and inward in waves): where x <= 0
/// it stands still, beside the moving part and far from it.
openvdb::FloatGrid::Ptr evolve(bool keepSettledLayers, int layers, int steps) {
  const shapes::Dumbbell dumbbell{openvdb::Vec3d(0.1, 0.2, -0.1), 9.0, 24.0, 3.5};
  SparseFieldOptions options;
  options.layers = layers;
  options.keepSettledLayers = keepSettledLayers;
  SparseField field = SparseField::fromLevelSet(
      *levelSetFromFunction(dumbbell, openvdb::BBoxd(openvdb::Vec3d(-26, -14, -14), openvdb::Vec3d(26, 14, 14)), 1.0),
      options);
  const ExternalForceSpeed speed{[](const openvdb::Vec3d& x, const openvdb::Vec3d&) {
                                   return x.x() > 0.0 ? 0.7 * std::sin(0.4 * x.x() + 0.3 * x.y()) : 0.0;
                                 },
                                 0.0, ForceSampling::kGridPoint};
  for (int i = 0; i < steps; ++i) field.step(speed);
  EXPECT_TRUE(checkInvariants(field).ok());
  return field.grid().deepCopy();  // the active set and the layers, with every value
}

TEST(SettledLayers, KeptLayersAreTheLayersTheRuleWouldRebuild) {
  for (const int layers : {2, 3}) {
    const auto kept = evolve(true, layers, 40);
    const auto rebuilt = evolve(false, layers, 40);
    std::string why;
    EXPECT_TRUE(test::identical(*kept, *rebuilt, &why)) << layers << " layers: " << why;
  }
}

}  // namespace
}  // namespace levelfuse
