// A reconstruction whose evolution the ranks of an MPI job share, one slab
// of every grid each, gives one process's result bit for bit, at rank 0, or
// in pieces, one at each rank.

#include "support/NoisyTorus.h"
#include "support/TestSupport.h"

#include <levelfuse/mpi/RankTeam.h>
#include <levelfuse/recon/Reconstructor.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace levelfuse {
namespace {

void expectSharedRunIsOneProcesssRun(DataTermSource source) {
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.levels = 3;
  options.dataTerm = source;
  const Reconstructor reconstructor(test::noisyTorusScans(), options);
  const mpi::RankTeam team;
  const ReconstructionResult alone = reconstructor.run();
  const ReconstructionResult shared = reconstructor.run({}, {}, &team);
  ASSERT_EQ(alone.levels.size(), shared.levels.size());
  for (std::size_t l = 0; l < alone.levels.size(); ++l) {
    EXPECT_EQ(alone.levels[l].iterations, shared.levels[l].iterations) << "grid " << l << ", rank " << team.rank();
    EXPECT_EQ(alone.levels[l].activeSetVoxels, shared.levels[l].activeSetVoxels) << "grid " << l;
    EXPECT_EQ(alone.levels[l].bandVoxels, shared.levels[l].bandVoxels) << "grid " << l;
  }
  if (team.rank() != 0) {
    EXPECT_FALSE(shared.levelSet) << "only the first rank holds the result";
    return;
  }
  ASSERT_TRUE(shared.levelSet && shared.weight);
  std::string why;
  EXPECT_TRUE(test::identical(*alone.levelSet, *shared.levelSet, &why)) << why;
  EXPECT_TRUE(test::identical(*alone.weight, *shared.weight, &why)) << why;
  EXPECT_GT(alone.levels.back().iterations, 4);
}

TEST(SharedReconstruction, TheDataTermFromTheMapsGivesOneProcesssSurface) {
  expectSharedRunIsOneProcesssRun(DataTermSource::kPerMap);
}

TEST(SharedReconstruction, TheDataTermFromGridsGivesOneProcesssSurface) {
  expectSharedRunIsOneProcesssRun(DataTermSource::kGrids);
}

TEST(SharedReconstruction, EachRankKeepsItsPieceOfOneProcesssSurface) {
  // Every rank keeps its slab's piece of the output: the level set one
  // process makes, clipped to the piece's x range (its metadata), tiles and
  // nodes alike, and that piece's weight; together the pieces hold it all.
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.levels = 3;
  const ReconstructionResult alone = Reconstructor(test::noisyTorusScans(), options).run();
  options.keepPieces = true;
  const mpi::RankTeam team;
  const ReconstructionResult mine = Reconstructor(test::noisyTorusScans(), options).run({}, {}, &team);
  ASSERT_TRUE(mine.levelSet && mine.weight) << "rank " << team.rank();
  EXPECT_EQ(mine.levelSet->metaValue<openvdb::Int32>("levelfuse_piece"), team.rank());
  EXPECT_EQ(mine.levelSet->metaValue<openvdb::Int32>("levelfuse_pieces"), team.size());
  SlabBounds slab;
  if (team.rank() > 0) slab.begin = mine.levelSet->metaValue<openvdb::Int32>("levelfuse_piece_begin_x");
  if (team.rank() + 1 < team.size()) slab.end = mine.levelSet->metaValue<openvdb::Int32>("levelfuse_piece_end_x");
  const openvdb::FloatGrid::Ptr clipped = test::clippedToSlab(*alone.levelSet, slab);
  std::string why;
  EXPECT_TRUE(test::identical(*clipped, *mine.levelSet, &why)) << "rank " << team.rank() << ": " << why;
  EXPECT_TRUE(test::sameTreeBytes(*clipped, *mine.levelSet)) << "rank " << team.rank();
  const openvdb::FloatGrid::ConstAccessor weight = alone.weight->getConstAccessor();
  std::size_t otherWeights = 0;
  for (auto w = mine.weight->cbeginValueOn(); w; ++w) otherWeights += *w != weight.getValue(w.getCoord());
  EXPECT_EQ(otherWeights, 0u) << "rank " << team.rank();
  EXPECT_EQ(team.total(mine.levelSet->activeVoxelCount()), alone.levelSet->activeVoxelCount());
  EXPECT_EQ(team.total(mine.weight->activeVoxelCount()), alone.weight->activeVoxelCount());
}

}  // namespace
}  // namespace levelfuse
