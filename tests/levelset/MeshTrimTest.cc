// Meshes trimmed by a weight grid stay valid indexed meshes.

#include "support/TestSupport.h"

#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/MeshTrim.h>

#include <gtest/gtest.h>

#include <set>

namespace levelfuse {
namespace {

/// Weight 1 on the band where x > 0, 0 elsewhere.
openvdb::FloatGrid::Ptr rightHalfWeight(const openvdb::FloatGrid& levelSet) {
  auto weight = openvdb::FloatGrid::create(0.0f);
  weight->setTransform(levelSet.transform().copy());
  weight->setTree(std::make_shared<openvdb::FloatTree>(levelSet.tree(), 0.0f, openvdb::TopologyCopy()));
  for (auto it = weight->beginValueOn(); it; ++it)
    it.setValue(weight->indexToWorld(it.getCoord()).x() > 0.0 ? 1.0f : 0.0f);
  return weight;
}

TEST(MeshTrim, KeepsTheTrianglesOfWeightAndOnlyTheVerticesTheyUse) {
  const auto sphere = test::makeSphere(12.0);
  const TriangleMesh closed = meshFromLevelSet(*sphere);
  const TriangleMesh trimmed = trimMesh(closed, *rightHalfWeight(*sphere), 0.5);
  ASSERT_GT(trimmed.triangleCount(), closed.triangleCount() * 4 / 10);
  ASSERT_LT(trimmed.triangleCount(), closed.triangleCount() * 6 / 10);
  std::set<std::uint32_t> used(trimmed.triangles.begin(), trimmed.triangles.end());
  ASSERT_EQ(used.size(), trimmed.vertexCount()) << "every vertex is used";
  EXPECT_EQ(*used.rbegin() + 1, trimmed.vertexCount()) << "indices within range";
  for (std::size_t t = 0; t < trimmed.triangleCount(); ++t) {
    double x = 0.0;
    for (int k = 0; k < 3; ++k) x += trimmed.xyz[3 * trimmed.triangles[3 * t + k]] / 3.0;
    ASSERT_GT(x, -0.5) << "triangle " << t << " lies where the weight is 0";
  }
  // The same triangles as the closed mesh's, in the same order and orientation.
  std::size_t t = 0;
  for (std::size_t c = 0; c < closed.triangleCount() && t < trimmed.triangleCount(); ++c) {
    bool same = true;
    for (int k = 0; k < 3; ++k)
      for (int axis = 0; axis < 3; ++axis)
        same &= closed.xyz[3 * closed.triangles[3 * c + k] + axis] ==
                trimmed.xyz[3 * trimmed.triangles[3 * t + k] + axis];
    t += same;
  }
  EXPECT_EQ(t, trimmed.triangleCount());
}

TEST(MeshTrim, KeepsAllOrNothingAtTheExtremes) {
  const auto sphere = test::makeSphere(8.0);
  const TriangleMesh closed = meshFromLevelSet(*sphere);
  const auto weight = rightHalfWeight(*sphere);
  const TriangleMesh all = trimMesh(closed, *weight, 0.0);
  EXPECT_EQ(all.triangles, closed.triangles);
  EXPECT_EQ(all.xyz, closed.xyz);
  const TriangleMesh none = trimMesh(closed, *weight, 2.0);
  EXPECT_EQ(none.triangleCount(), 0u);
  EXPECT_EQ(none.vertexCount(), 0u);
}

TEST(MeshTrim, RefusesIndicesOutOfRangeAndAThresholdThatIsNotANumber) {
  const auto sphere = test::makeSphere(8.0);
  const auto weight = rightHalfWeight(*sphere);
  TriangleMesh broken;
  broken.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  broken.triangles = {0, 1, 3};
  EXPECT_THROW(trimMesh(broken, *weight, 0.5), std::invalid_argument);
  EXPECT_THROW(trimMesh(meshFromLevelSet(*sphere), *weight, std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse
