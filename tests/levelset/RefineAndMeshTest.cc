// Refining a level set to half its voxel size, and meshing its zero set.

#include "support/TestSupport.h"

#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/Refine.h>
#include <levelfuse/levelset/ZeroCrossings.h>

#include <openvdb/tools/Diagnostics.h>
#include <openvdb/tools/Interpolation.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace levelfuse {
namespace {

TEST(Refine, HalvesTheVoxelAndKeepsTheSurface) {
  const openvdb::Vec3d centre(0.3, -0.2, 0.1);
  const auto coarse = test::makeSphere(12.0, centre, 0.1);  // radius 1.2
  const auto fine = refineLevelSet(*coarse);
  EXPECT_NEAR(fine->voxelSize()[0], 0.5 * coarse->voxelSize()[0], 1e-12);
  EXPECT_EQ(fine->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(openvdb::tools::checkLevelSet(*fine, 6), "");
  // The zero set is the trilinear interpolant's: as near the sphere as the
  // coarse grid's, measured in coarse voxels.
  const auto sphere = [&](const openvdb::Vec3d& p) { return (p - centre).length() - 1.2; };
  const double coarseRms = rmsOver(zeroCrossings(*coarse), sphere) / 0.1;
  const double fineRms = rmsOver(zeroCrossings(*fine), sphere) / 0.1;
  EXPECT_LT(coarseRms, 0.01);
  EXPECT_LT(fineRms, 0.02);
  EXPECT_GT(zeroCrossings(*fine).size(), 3.5 * zeroCrossings(*coarse).size());
  // Inside stays inside, far from the band too (tiles are carried over).
  EXPECT_LT(fine->tree().getValue(openvdb::Coord::round(fine->worldToIndex(centre))), 0.0f);
  EXPECT_GT(fine->tree().getValue(openvdb::Coord::round(fine->worldToIndex(centre + openvdb::Vec3d(3, 0, 0)))), 0.0f);
}

TEST(Refine, ReadsAsTheCoarseLevelSetSampledWithTilesWhereNoBandReaches) {
  // A sphere whose coarse leaves hold voxels far from its band too: a fine
  // leaf node the band does not reach, and beside which no sign changes,
  // becomes a tile of its side; every fine voxel over the coarse leaves reads
  // the coarse level set sampled there, clamped to the band.
  const auto coarse = test::makeSphere(12.0, openvdb::Vec3d(0.3, -0.2, 0.1), 0.1);
  const auto fine = refineLevelSet(*coarse);
  const float width = fine->background();
  const openvdb::FloatGrid::ConstAccessor coarseValues = coarse->getConstAccessor();
  const openvdb::FloatGrid::ConstAccessor fineValues = fine->getConstAccessor();
  std::size_t tiles = 0, leaves = 0, voxels = 0;
  for (auto leaf = coarse->tree().cbeginLeaf(); leaf; ++leaf)
    for (int child = 0; child < 8; ++child) {
      const openvdb::Coord& o = leaf->origin();
      const openvdb::Coord origin(2 * o.x() + (child & 1) * 8, 2 * o.y() + ((child >> 1) & 1) * 8,
                                  2 * o.z() + (child >> 2) * 8);
      const bool isLeaf = fine->tree().probeConstLeaf(origin) != nullptr;
      (isLeaf ? leaves : tiles) += 1;
      for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
          for (int k = 0; k < 8; ++k) {
            const openvdb::Coord ijk = origin.offsetBy(i, j, k);
            const float sampled = openvdb::tools::BoxSampler::sample(coarseValues, ijk.asVec3d() * 0.5);
            const bool inBand = std::fabs(sampled) < width;
            ASSERT_EQ(fineValues.getValue(ijk), inBand ? sampled : (sampled < 0.0f ? -width : width)) << ijk;
            ASSERT_EQ(fineValues.isValueOn(ijk), inBand) << ijk;
            if (!isLeaf) {
              ASSERT_FALSE(inBand) << ijk;
            }
            ++voxels;
          }
    }
  EXPECT_GT(tiles, leaves / 4) << "fine leaf nodes beyond the band are tiles";
  EXPECT_GT(leaves, 0u);
  EXPECT_EQ(openvdb::tools::checkLevelSet(*fine, 6), "");
  EXPECT_EQ(voxels, 512 * 8 * coarse->tree().leafCount());
}

TEST(Refine, RefusesWhatIsNotALevelSet) {
  auto fog = openvdb::FloatGrid::create(0.0f);
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  EXPECT_THROW(refineLevelSet(*fog), std::invalid_argument);
}

TEST(Mesh, IsClosedOutwardFacingAndOnTheSurface) {
  const openvdb::Vec3d centre(0.3, -0.2, 0.1);
  const auto sphere = test::makeSphere(20.0, centre, 0.05);  // radius 1
  const TriangleMesh mesh = meshFromLevelSet(*sphere);
  ASSERT_GT(mesh.triangleCount(), 1000u);
  EXPECT_NEAR(mesh.volume(), 4.0 / 3.0 * M_PI, 0.01 * 4.0 / 3.0 * M_PI);  // positive: outward
  EXPECT_NEAR(mesh.area(), 4.0 * M_PI, 0.02 * 4.0 * M_PI);
  double worst = 0.0;
  for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
    const openvdb::Vec3d p(mesh.xyz[3 * i], mesh.xyz[3 * i + 1], mesh.xyz[3 * i + 2]);
    worst = std::max(worst, std::fabs((p - centre).length() - 1.0));
  }
  EXPECT_LT(worst, 0.01);
  // Closed: every edge is shared by exactly two triangles, in opposite directions.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3)
    for (int k = 0; k < 3; ++k) ++edges[{mesh.triangles[t + k], mesh.triangles[t + (k + 1) % 3]}];
  for (const auto& [edge, count] : edges) {
    ASSERT_EQ(count, 1);
    ASSERT_EQ(edges.count({edge.second, edge.first}), 1u);
  }
}

TEST(Mesh, BackToALevelSetOfAnyVoxel) {
  const openvdb::Vec3d centre(0.3, -0.2, 0.1);
  const TriangleMesh mesh = meshFromLevelSet(*test::makeSphere(20.0, centre, 0.05));  // radius 1
  const openvdb::FloatGrid::Ptr levelSet = levelSetFromMesh(mesh, 0.02, 4.0f);
  EXPECT_EQ(levelSet->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_NEAR(levelSet->voxelSize().x(), 0.02, 1e-12);
  EXPECT_FLOAT_EQ(levelSet->background(), 4.0f * 0.02f);
  // Signed distances, negative inside, world units.
  const openvdb::FloatGrid::ConstAccessor values = levelSet->getConstAccessor();
  for (const double offset : {-0.05, 0.0, 0.03}) {
    const openvdb::Vec3d p = centre + openvdb::Vec3d(0.0, 0.0, 1.0 + offset);
    EXPECT_NEAR(values.getValue(levelSet->transform().worldToIndexNodeCentered(p)), offset, 0.015) << offset;  // half a voxel of rounding
  }
  EXPECT_LT(values.getValue(levelSet->transform().worldToIndexNodeCentered(centre)), 0.0f);
}

}  // namespace
}  // namespace levelfuse
