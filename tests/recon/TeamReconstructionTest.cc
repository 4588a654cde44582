// A reconstruction whose evolution a team shares, one slab of every grid
// each, gives one process's result bit for bit: the team here is threads of
// one process (support/ThreadTeam.h), so the path runs under AddressSanitizer
// too; tests/mpi runs it on the ranks of an MPI job.

#include "RoomFrames.h"
#include "support/NoisyTorus.h"
#include "support/TestSupport.h"
#include "support/ThreadTeam.h"

#include <levelfuse/recon/Fusion.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/SharedData.h>
#include <levelfuse/scan/PackedRangeMap.h>
#include <levelfuse/synth/Synth.h>

#include <gtest/gtest.h>
#include <openvdb/tools/Composite.h>

#include <algorithm>
#include <functional>
#include <regex>
#include <string>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

/// Expects `mine`, a rank's result of a team's run, to be `alone`'s (the
/// first rank's surface and weight, the others' none), grid by grid.
void expectOneProcesssResult(const ReconstructionResult& alone, const ReconstructionResult& mine, int rank) {
  ASSERT_EQ(alone.levels.size(), mine.levels.size());
  for (std::size_t l = 0; l < alone.levels.size(); ++l) {
    EXPECT_EQ(alone.levels[l].iterations, mine.levels[l].iterations) << "grid " << l << ", rank " << rank;
    EXPECT_EQ(alone.levels[l].activeSetVoxels, mine.levels[l].activeSetVoxels) << "grid " << l << ", rank " << rank;
    EXPECT_EQ(alone.levels[l].bandVoxels, mine.levels[l].bandVoxels) << "grid " << l << ", rank " << rank;
  }
  if (rank > 0) {
    EXPECT_FALSE(mine.levelSet || mine.weight) << "only the first rank holds the result";
    return;
  }
  ASSERT_TRUE(mine.levelSet && mine.weight);
  std::string why;
  EXPECT_TRUE(test::identical(*alone.levelSet, *mine.levelSet, &why)) << why;
  EXPECT_TRUE(test::sameTreeBytes(*alone.levelSet, *mine.levelSet)) << "the trees' tiles or nodes differ";
  EXPECT_TRUE(test::identical(*alone.weight, *mine.weight, &why)) << why;
}

/// Expects each rank's bytes of the data term, `held`, to be more than a fifth
/// of the whole's `whole` and below `most` of it, and their sum below `sum` of it.
void expectSharesOfTheData(const std::vector<std::size_t>& held, std::size_t whole, double most, double sum) {
  double shares = 0.0;
  for (std::size_t r = 0; r < held.size(); ++r) {
    const double share = static_cast<double>(held[r]) / static_cast<double>(whole);
    EXPECT_GT(share, 0.2) << "rank " << r;
    EXPECT_LT(share, most) << "rank " << r;
    shares += share;
  }
  EXPECT_LT(shares, sum);
}

void expectTeamRunIsOneProcesssRun(DataTermSource source, int ranks) {
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.levels = 3;
  options.dataTerm = source;
  const Reconstructor reconstructor(test::noisyTorusScans(), options);
  const ReconstructionResult alone = reconstructor.run();
  std::vector<ReconstructionResult> shared(static_cast<std::size_t>(ranks));
  test::runOnThreadTeam(ranks, [&](const SlabTeam& team) {
    shared[static_cast<std::size_t>(team.rank())] = reconstructor.run({}, {}, &team);
  });
  for (int r = 0; r < ranks; ++r) expectOneProcesssResult(alone, shared[static_cast<std::size_t>(r)], r);
  // Every grid is cut afresh: the ranks' shares of the finest grid's leaf
  // nodes are about even (whole columns of leaves, cut before the grid evolved).
  std::size_t leaves = 0, most = 0;
  for (const ReconstructionResult& mine : shared) {
    leaves += mine.levels.back().ownLeafNodes;
    most = std::max(most, mine.levels.back().ownLeafNodes);
  }
  EXPECT_EQ(leaves, alone.levels.back().ownLeafNodes);
  EXPECT_LT(static_cast<double>(most), 1.4 * static_cast<double>(leaves) / ranks);
  EXPECT_GT(alone.levels.back().iterations, 4);
}

TEST(TeamReconstruction, TwoRanksWithTheDataTermFromTheMapsGiveOneProcesssSurface) {
  expectTeamRunIsOneProcesssRun(DataTermSource::kPerMap, 2);
}

TEST(TeamReconstruction, ThreeRanksWithTheDataTermFromGridsGiveOneProcesssSurface) {
  expectTeamRunIsOneProcesssRun(DataTermSource::kGrids, 3);
}

/// Depth frames of a room at `voxelSize`: one grid, the data term from grids.
ReconstructionOptions roomOptions(double voxelSize) {
  ReconstructionOptions options;
  options.voxelSize = voxelSize;
  options.dataTerm = DataTermSource::kGrids;
  return options;
}

TEST(TeamReconstruction, RanksThatEachHoldTheirSlabOfTheDataGiveOneProcesssSurface) {
  // Depth frames of a room, one grid: each rank integrates the frames only
  // within its slab and the voxels it reads beyond, and makes its slab of the
  // initial model of those data alone; the surface and its weight are one
  // process's, bit for bit, with the cuts of 2, 3 and 4 ranks (at 1 cm, the
  // next test).
  const Reconstructor reconstructor(roomFrames().reconstruction, roomOptions(0.02));
  ASSERT_EQ(reconstructor.settings().levels, 1);
  const ReconstructionResult alone = reconstructor.run();
  EXPECT_GT(alone.levels.back().iterations, 2);
  for (const int ranks : {2, 3, 4}) {
    std::vector<ReconstructionResult> shared(static_cast<std::size_t>(ranks));
    test::runOnThreadTeam(ranks, [&](const SlabTeam& team) {
      shared[static_cast<std::size_t>(team.rank())] = reconstructor.run({}, {}, &team);
    });
    for (int r = 0; r < ranks; ++r) {
      SCOPED_TRACE(std::to_string(ranks) + " ranks");
      expectOneProcesssResult(alone, shared[static_cast<std::size_t>(r)], r);
    }
  }
}

TEST(TeamReconstruction, RanksThatHoldTheirSlabOfTheDataKeepPiecesOfOneProcesssSurface) {
  // Each of 3 ranks integrates its slab of the room's frames alone and keeps
  // its piece of the output: the level set one process makes, clipped to
  // the piece, tiles and nodes alike, weighed as one process weighs it.
  const std::vector<RangeMap> frames = roomFrames().reconstruction;
  ReconstructionOptions options = roomOptions(0.02);
  const ReconstructionResult alone = Reconstructor(frames, options).run();
  options.keepPieces = true;
  const Reconstructor inPieces(frames, options);
  std::vector<ReconstructionResult> shared(3);
  test::runOnThreadTeam(3, [&](const SlabTeam& team) {
    shared[static_cast<std::size_t>(team.rank())] = inPieces.run({}, {}, &team);
  });
  openvdb::Index64 voxels = 0;
  for (int r = 0; r < 3; ++r) {
    const ReconstructionResult& mine = shared[static_cast<std::size_t>(r)];
    ASSERT_TRUE(mine.levelSet && mine.weight) << "rank " << r;
    SlabBounds slab;
    if (r > 0) slab.begin = mine.levelSet->metaValue<openvdb::Int32>("levelfuse_piece_begin_x");
    if (r < 2) slab.end = mine.levelSet->metaValue<openvdb::Int32>("levelfuse_piece_end_x");
    const openvdb::FloatGrid::Ptr clipped = test::clippedToSlab(*alone.levelSet, slab);
    std::string why;
    EXPECT_TRUE(test::identical(*clipped, *mine.levelSet, &why)) << "rank " << r << ": " << why;
    EXPECT_TRUE(test::sameTreeBytes(*clipped, *mine.levelSet)) << "rank " << r;
    const openvdb::FloatGrid::ConstAccessor weight = alone.weight->getConstAccessor();
    std::size_t otherWeights = 0;
    for (auto w = mine.weight->cbeginValueOn(); w; ++w) otherWeights += *w != weight.getValue(w.getCoord());
    EXPECT_EQ(otherWeights, 0u) << "rank " << r;
    EXPECT_TRUE(test::weighsTheBand(*mine.weight, *mine.levelSet)) << "rank " << r;
    voxels += mine.levelSet->activeVoxelCount();
  }
  EXPECT_EQ(voxels, alone.levelSet->activeVoxelCount());
}

/// The converter's way, in one process: `maps` packed, the options resolved
/// from their summary, their fusion and its run.
struct FusedByOneProcess {
  PackedScans packed;
  ReconstructionSettings resolved;
  std::unique_ptr<Fusion> whole;
  ReconstructionResult alone;
};

FusedByOneProcess fusedByOneProcess(std::vector<RangeMap> maps, const ReconstructionOptions& options) {
  FusedByOneProcess one;
  for (RangeMap& map : maps) one.packed.add(std::move(map));
  one.resolved = resolveReconstructionSettings(options, one.packed.summary);
  one.whole = fusePackedScans(one.packed, one.resolved);
  one.alone = Reconstructor(*one.whole, options).run();
  return one;
}

/// Expects a fusion of `one`'s scans made for a team of two to be refused by
/// a reconstructor without the team: its run, and the weight of a surface.
void expectRefusedWithoutItsTeam(const FusedByOneProcess& one, const ReconstructionOptions& options) {
  test::runOnThreadTeam(2, [&](const SlabTeam& team) {
    const std::unique_ptr<Fusion> mine = fusePackedScans(one.packed, one.resolved, {}, {}, &team);
    if (team.rank() == 0) {
      EXPECT_THROW(Reconstructor(*mine, options).run(), std::invalid_argument);
      EXPECT_THROW(Reconstructor(*mine, options).surfaceWeight(*one.alone.levelSet), std::invalid_argument);
    }
  });
}

TEST(TeamReconstruction, AFusionOfOneSlabOfTheDataHoldsItsShareAndReconstructsOnItsTeam) {
  // The converter's way: each rank fuses the packed frames into its slab of
  // the data (fusePackedScans with the team), then reconstructs on the team.
  const ReconstructionOptions options = roomOptions(0.01);
  const FusedByOneProcess one = fusedByOneProcess(roomFrames().reconstruction, options);
  constexpr int kRanks = 3;
  std::vector<ReconstructionResult> shared(kRanks);
  std::vector<std::size_t> dataBytes(kRanks);
  std::vector<SlabBounds> dataSlabs(kRanks);
  test::runOnThreadTeam(kRanks, [&](const SlabTeam& team) {
    const std::unique_ptr<Fusion> mine = fusePackedScans(one.packed, one.resolved, {}, {}, &team);
    const std::size_t r = static_cast<std::size_t>(team.rank());
    ASSERT_TRUE(mine->dataSlab());
    dataSlabs[r] = *mine->dataSlab();
    dataBytes[r] = mine->dataTerm(0).memoryBytes();
    const Reconstructor reconstructor(*mine, options);
    EXPECT_THROW(reconstructor.linearSolution(), std::invalid_argument) << "one slab of the data is no linear solution";
    shared[r] = reconstructor.run({}, {}, &team);
  });
  for (int r = 0; r < kRanks; ++r) expectOneProcesssResult(one.alone, shared[static_cast<std::size_t>(r)], r);
  // The slabs' data follow one another, each reaching its neighbours' by the margin.
  EXPECT_FALSE(dataSlabs.front().hasLower());
  EXPECT_FALSE(dataSlabs.back().hasHigher());
  for (int r = 1; r < kRanks; ++r)
    EXPECT_EQ(ownSlabOf(dataSlabs[static_cast<std::size_t>(r - 1)]).end, ownSlabOf(dataSlabs[static_cast<std::size_t>(r)]).begin);
  // Each holds a part of the data term. Its margins are wide beside a room
  // this small: the middle rank's slab is 13 columns of leaf nodes, its data
  // 19 (measured: the ranks hold 0.46, 0.61 and 0.45 of the whole's bytes).
  expectSharesOfTheData(dataBytes, one.whole->dataTerm(0).memoryBytes(), 0.7, 1.65);
  // Without its team, a fusion of one slab reconstructs nothing.
  expectRefusedWithoutItsTeam(one, options);
}

TEST(TeamReconstruction, RanksThatIntegrateTheFinerGridsWithinTheirSlabsGiveOneProcesssSurface) {
  // Coarse to fine from grids, the converter's way: the coarsest grid's
  // data term is whole on every rank, each finer grid's integrated by each
  // rank within its slab once that grid is cut (Fusion::deferLevel).
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.levels = 3;
  options.dataTerm = DataTermSource::kGrids;
  const FusedByOneProcess one = fusedByOneProcess(test::noisyTorusScans(), options);
  constexpr int kRanks = 3;
  std::vector<ReconstructionResult> shared(kRanks);
  std::vector<std::size_t> heldBytes(kRanks);
  test::runOnThreadTeam(kRanks, [&](const SlabTeam& team) {
    const std::unique_ptr<Fusion> mine = fusePackedScans(one.packed, one.resolved, {}, {}, &team);
    ASSERT_TRUE(!mine->deferred(0) && mine->deferred(1) && mine->deferred(2));
    EXPECT_EQ(mine->dataTerm(2).memoryBytes(), DataTermGrids(0.02, one.whole->dataTerm(2).window(), 0.0).memoryBytes())
        << "the finest grid waits for its cut";
    const Reconstructor reconstructor(*mine, options);
    EXPECT_THROW(reconstructor.linearSolution(), std::invalid_argument);
    shared[static_cast<std::size_t>(team.rank())] = reconstructor.run({}, {}, &team);
    heldBytes[static_cast<std::size_t>(team.rank())] = shared[static_cast<std::size_t>(team.rank())].levels.back().slabDataTermBytes;
  });
  for (int r = 0; r < kRanks; ++r) expectOneProcesssResult(one.alone, shared[static_cast<std::size_t>(r)], r);
  // Each rank's slab of the finest grid's data term: its part of the torus
  // and 24 voxels beyond each cut, wide beside a torus 17 columns of leaf
  // nodes across (measured: 0.89, 0.91 and 0.52 of the whole grid's bytes).
  expectSharesOfTheData(heldBytes, one.whole->dataTerm(2).memoryBytes(), 0.95, 2.45);
  EXPECT_EQ(one.alone.levels.back().slabDataTermBytes, 0u);
  // Without its team, a fusion that defers a grid reconstructs nothing.
  expectRefusedWithoutItsTeam(one, options);
}

TEST(TeamReconstruction, ARankThatFailsStopsTheOthers) {
  // The team's other ranks stop at their next collective, not hang.
  const Reconstructor reconstructor(test::noisyTorusScans(), [] {
    ReconstructionOptions o;
    o.voxelSize = 0.04;
    o.levels = 2;
    return o;
  }());
  EXPECT_THROW(test::runOnThreadTeam(3,
                                     [&](const SlabTeam& team) {
                                       reconstructor.run(
                                           [&](const ReconstructionProgress& p) {
                                             return !(team.rank() == 1 && p.iteration == 3);
                                           },
                                           {}, &team);
                                     }),
               ReconstructionCancelled);
}

TEST(TeamReconstruction, RanksThatKeepTheirPiecesHoldTheWholeSurfaceBetweenThem) {
  // Each of 3 ranks keeps its slab's piece of the level set, with the weight
  // and colour of that piece: each piece is one process's surface within the
  // slab, and their union is the whole of it. The scans saw a torus red at
  // x > 0 and blue elsewhere.
  std::vector<RangeMap> scans = test::noisyTorusScans();
  for (RangeMap& map : scans)
    synth::paintReadings(map, synth::twoColours(Vec3d(0.0), Vec3d(1, 0, 0), Rgb8{200, 40, 30}, Rgb8{30, 60, 200}));
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.levels = 3;
  const Reconstructor reconstructor(scans, options);
  const ReconstructionResult alone = reconstructor.run();
  ASSERT_TRUE(alone.colour);
  options.keepPieces = true;
  const Reconstructor inPieces(scans, options);
  std::vector<ReconstructionResult> shared(3);
  test::runOnThreadTeam(3, [&](const SlabTeam& team) {
    shared[static_cast<std::size_t>(team.rank())] = inPieces.run({}, {}, &team);
  });
  openvdb::FloatGrid::Ptr united;
  openvdb::Index64 weighedVoxels = 0, colouredVoxels = 0;
  for (int r = 0; r < 3; ++r) {
    const ReconstructionResult& mine = shared[static_cast<std::size_t>(r)];
    ASSERT_TRUE(mine.levelSet && mine.weight) << "rank " << r;
    EXPECT_EQ(mine.levelSet->metaValue<openvdb::Int32>("levelfuse_piece"), r);
    EXPECT_EQ(mine.levelSet->metaValue<openvdb::Int32>("levelfuse_pieces"), 3);
    EXPECT_EQ(mine.levelSet->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_EQ(mine.levelSet->metaValue<openvdb::Int32>("levelfuse_iterations"),
              alone.levelSet->metaValue<openvdb::Int32>("levelfuse_iterations"));
    EXPECT_GT(mine.levelSet->activeVoxelCount(), alone.levelSet->activeVoxelCount() / 6) << "rank " << r;
    // The weight of the piece's voxels, as one process weighs them.
    EXPECT_TRUE(test::weighsTheBand(*mine.weight, *mine.levelSet)) << "rank " << r;
    const openvdb::FloatGrid::ConstAccessor whole = alone.weight->getConstAccessor();
    std::size_t differ = 0;
    for (auto w = mine.weight->cbeginValueOn(); w; ++w) differ += *w != whole.getValue(w.getCoord());
    EXPECT_EQ(differ, 0u) << "rank " << r;
    weighedVoxels += mine.weight->activeVoxelCount();
    // The colour of the piece's voxels, as one process sees it.
    ASSERT_TRUE(mine.colour) << "rank " << r;
    const openvdb::Vec3fGrid::ConstAccessor wholeColour = alone.colour->getConstAccessor();
    std::size_t otherColours = 0;
    for (auto c = mine.colour->cbeginValueOn(); c; ++c) {
      otherColours += *c != wholeColour.getValue(c.getCoord()) || !wholeColour.isValueOn(c.getCoord());
      otherColours += !mine.levelSet->tree().isValueOn(c.getCoord());
    }
    EXPECT_EQ(otherColours, 0u) << "rank " << r;
    colouredVoxels += mine.colour->activeVoxelCount();
    if (!united) united = mine.levelSet->deepCopy();
    else openvdb::tools::csgUnion(united->tree(), mine.levelSet->deepCopy()->tree());
  }
  EXPECT_EQ(weighedVoxels, alone.weight->activeVoxelCount());
  EXPECT_EQ(colouredVoxels, alone.colour->activeVoxelCount());
  EXPECT_FALSE(shared.front().levelSet->getMetadata<openvdb::Int32Metadata>("levelfuse_piece_begin_x"));
  EXPECT_FALSE(shared.back().levelSet->getMetadata<openvdb::Int32Metadata>("levelfuse_piece_end_x"));
  EXPECT_EQ(shared[0].levelSet->metaValue<openvdb::Int32>("levelfuse_piece_end_x"),
            shared[1].levelSet->metaValue<openvdb::Int32>("levelfuse_piece_begin_x"));
  std::string why;
  EXPECT_TRUE(test::identical(*alone.levelSet, *united, &why)) << why;
}

/// The memory a refusal (InsufficientMemory) of `run` says is needed, in bytes; 0 if it runs.
double neededBytes(const std::function<void()>& run) {
  try {
    run();
  } catch (const InsufficientMemory& e) {
    std::smatch m;
    const std::string what = e.what();
    if (!std::regex_search(what, m, std::regex("needs about ([0-9.]+) (bytes|KiB|MiB|GiB)"))) return -1.0;
    const double units[] = {1.0, 1024.0, 1024.0 * 1024.0, 1024.0 * 1024.0 * 1024.0};
    const std::string unit = m[2];
    const int k = unit == "bytes" ? 0 : unit == "KiB" ? 1 : unit == "MiB" ? 2 : 3;
    return std::stod(m[1]) * units[k];
  }
  return 0.0;
}

TEST(TeamReconstruction, EachRankAsksForItsShareOfTheFinestGridsMemory) {
  // Four ranks each need their slab's share of the finest grid (with a
  // margin for cuts at whole columns), and the first the whole output.
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.levels = 3;
  options.memoryBudget = MemoryBudget(2 * 1024 * 1024);  // above the initial model's needs
  const Reconstructor tight(test::noisyTorusScans(), options);
  const double whole = neededBytes([&] { tight.run(); });
  std::vector<double> shares(4);
  test::runOnThreadTeam(4, [&](const SlabTeam& team) {
    shares[static_cast<std::size_t>(team.rank())] = neededBytes([&] { tight.run({}, {}, &team); });
  });
  ASSERT_GT(whole, 1e6) << "one process's refusal names the finest grid's memory";
  EXPECT_NEAR(shares[0] / whole, kOutputBytesPerActiveVoxel / kPeakBytesPerActiveVoxel, 0.01);
  for (std::size_t r = 1; r < 4; ++r) EXPECT_NEAR(shares[r] / whole, kSlabShareMargin / 4.0, 0.01) << "rank " << r;
  // Ranks that keep their pieces of the output each need their share alone.
  ReconstructionOptions piecesOptions = options;
  piecesOptions.keepPieces = true;
  const Reconstructor inPieces(test::noisyTorusScans(), piecesOptions);
  double firstsPiece = 0.0;
  test::runOnThreadTeam(4, [&](const SlabTeam& team) {
    const double needed = neededBytes([&] { inPieces.run({}, {}, &team); });
    if (team.rank() == 0) firstsPiece = needed;
  });
  EXPECT_NEAR(firstsPiece / whole, kSlabShareMargin / 4.0, 0.01);
  // Within a budget of 70% of the whole, one process refuses and the team runs.
  options.memoryBudget = MemoryBudget(static_cast<std::uint64_t>(0.7 * whole));
  const Reconstructor reconstructor(test::noisyTorusScans(), options);
  EXPECT_THROW(reconstructor.run(), InsufficientMemory);
  std::vector<bool> made(4);
  test::runOnThreadTeam(4, [&](const SlabTeam& team) {
    made[static_cast<std::size_t>(team.rank())] = static_cast<bool>(reconstructor.run({}, {}, &team).levelSet);
  });
  EXPECT_TRUE(made[0]);
}

}  // namespace
}  // namespace levelfuse
