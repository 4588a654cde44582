// A reconstruction whose evolution the ranks of an MPI job share, one slab
// of every grid each, gives one process's result bit for bit, at rank 0, or
// in pieces, one at each rank.

#include "recon/RoomFrames.h"
#include "recon/StreetFrames.h"
#include "support/NoisyTorus.h"
#include "support/TestSupport.h"

#include <levelfuse/mpi/RankTeam.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/ScansReconstruction.h>
#include <levelfuse/recon/TeamScans.h>
#include <levelfuse/scan/PackedRangeMap.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace levelfuse {
namespace {

/// Expects the ranks' run of `reconstructor` to give its one process's
/// result, at rank 0; returns that result.
ReconstructionResult expectSharedRunIsOneProcesssRun(const Reconstructor& reconstructor) {
  const mpi::RankTeam team;
  const ReconstructionResult alone = reconstructor.run();
  const ReconstructionResult shared = reconstructor.run({}, {}, &team);
  EXPECT_EQ(alone.levels.size(), shared.levels.size());
  for (std::size_t l = 0; l < std::min(alone.levels.size(), shared.levels.size()); ++l) {
    EXPECT_EQ(alone.levels[l].iterations, shared.levels[l].iterations) << "grid " << l << ", rank " << team.rank();
    EXPECT_EQ(alone.levels[l].activeSetVoxels, shared.levels[l].activeSetVoxels) << "grid " << l;
    EXPECT_EQ(alone.levels[l].bandVoxels, shared.levels[l].bandVoxels) << "grid " << l;
    EXPECT_EQ(team.total(shared.levels[l].ownLeafNodes), alone.levels[l].ownLeafNodes) << "grid " << l;
  }
  if (team.rank() != 0) {
    EXPECT_FALSE(shared.levelSet || shared.weight) << "only the first rank holds the result";
    return alone;
  }
  EXPECT_TRUE(shared.levelSet && shared.weight);
  if (!shared.levelSet || !shared.weight) return alone;
  std::string why;
  EXPECT_TRUE(test::identical(*alone.levelSet, *shared.levelSet, &why)) << why;
  EXPECT_TRUE(test::sameTreeBytes(*alone.levelSet, *shared.levelSet)) << "the trees' tiles or nodes differ";
  EXPECT_TRUE(test::identical(*alone.weight, *shared.weight, &why)) << why;
  return alone;
}

/// The noisy torus on 3 grids, the data term from `source`.
void expectTheTorusIsOneProcesss(DataTermSource source) {
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.levels = 3;
  options.dataTerm = source;
  const ReconstructionResult alone = expectSharedRunIsOneProcesssRun(Reconstructor(test::noisyTorusScans(), options));
  EXPECT_GT(alone.levels.back().iterations, 4);
}

TEST(SharedReconstruction, TheDataTermFromTheMapsGivesOneProcesssSurface) {
  expectTheTorusIsOneProcesss(DataTermSource::kPerMap);
}

TEST(SharedReconstruction, TheDataTermFromGridsGivesOneProcesssSurface) {
  expectTheTorusIsOneProcesss(DataTermSource::kGrids);
}

TEST(SharedReconstruction, DepthFramesGiveOneProcesssSurfaceWithEachRankHoldingItsSlabOfTheData) {
  // Depth frames of a room, one grid, the data term from grids: each rank
  // integrates the frames within its slab (and the voxels it reads beyond)
  // alone, and makes its slab of the initial model from them.
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.dataTerm = DataTermSource::kGrids;
  const Reconstructor reconstructor(roomFrames().reconstruction, options);
  ASSERT_EQ(reconstructor.settings().levels, 1);
  expectSharedRunIsOneProcesssRun(reconstructor);
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

TEST(SharedReconstruction, RanksThatReadTheFramesTheirSlabNeedsGiveOneProcesssPieces) {
  // Frames along a street: the ranks read them in turn, agree on the
  // settings and the cuts, and each then holds the frames its slab needs
  // (recon/TeamScans.h); each keeps its piece of one process's surface.
  const std::vector<RangeMap> frames = streetFrames();
  ReconstructionOptions options;
  options.voxelSize = 0.04;
  options.dataTerm = DataTermSource::kGrids;
  const ReconstructionResult alone = Reconstructor(frames, options).run();
  options.keepPieces = true;
  const mpi::RankTeam team;
  PackedScans read;
  std::vector<std::size_t> first;
  for (std::size_t n = 0; n < frames.size(); ++n)
    if (readFirstBy(n, team.rank(), team.size())) {
      read.add(RangeMap(frames[n]));
      first.push_back(n);
    }
  const ScanSummary whole = teamSummary(read.summary, team);
  const ReconstructionSettings settings = resolveReconstructionSettings(options, whole);
  const TeamScanPlan plan = planTeamScans(read, first, frames.size(), settings, false, team);
  ASSERT_TRUE(plan.slab);
  PackedScans needed;
  for (std::size_t n : plan.needed) needed.add(RangeMap(frames[n]));
  needed.summary = whole;
  EXPECT_LT(needed.maps.size(), frames.size() * 3 / 4) << "rank " << team.rank() << " holds most frames";
  EXPECT_EQ(team.total(needed.maps.size() > 0 ? 1 : 0), static_cast<std::uint64_t>(team.size()));
  ScansReconstruction made = prepareReconstruction(std::move(needed), settings, {}, {}, &team, &*plan.slab);
  const ReconstructionResult mine = made.reconstructor->run({}, {}, &team);
  ASSERT_TRUE(mine.levelSet) << "rank " << team.rank();
  const openvdb::FloatGrid::Ptr clipped = test::clippedToSlab(*alone.levelSet, plan.slab->own);
  std::string why;
  EXPECT_TRUE(test::identical(*clipped, *mine.levelSet, &why)) << "rank " << team.rank() << ": " << why;
  EXPECT_TRUE(test::sameTreeBytes(*clipped, *mine.levelSet)) << "rank " << team.rank();
  EXPECT_EQ(team.total(mine.levelSet->activeVoxelCount()), alone.levelSet->activeVoxelCount());
}

}  // namespace
}  // namespace levelfuse
