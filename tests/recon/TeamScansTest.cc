// The scans of a team read by the processes that need them
// (recon/TeamScans.h): the team agrees on the whole set's summary and cuts
// the slabs where one process holding every scan would; each process then
// holds the scans its slab needs, and the reconstruction is one process's,
// bit for bit. The team here is threads of one process (support/ThreadTeam.h).

#include "RoomFrames.h"
#include "StreetFrames.h"
#include "support/TestSupport.h"
#include "support/ThreadTeam.h"

#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/ScansReconstruction.h>
#include <levelfuse/recon/SharedData.h>
#include <levelfuse/recon/TeamScans.h>
#include <levelfuse/scan/PackedRangeMap.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace levelfuse {
namespace {

/// The scans of `all` numbered in `numbers`, packed, with their summary.
PackedScans scansNumbered(const std::vector<RangeMap>& all, const std::vector<std::size_t>& numbers) {
  PackedScans scans;
  for (std::size_t n : numbers) scans.add(RangeMap(all.at(n)));
  return scans;
}

/// The numbers of the scans of `all` that `team`'s process reads first (readFirstBy).
std::vector<std::size_t> readFirst(const std::vector<RangeMap>& all, const SlabTeam& team) {
  std::vector<std::size_t> numbers;
  for (std::size_t n = 0; n < all.size(); ++n)
    if (readFirstBy(n, team.rank(), team.size())) numbers.push_back(n);
  return numbers;
}

/// One grid, the data term from grids: the team shares the data in slabs.
ReconstructionOptions streetOptions() {
  ReconstructionOptions options;
  options.voxelSize = 0.04;
  options.dataTerm = DataTermSource::kGrids;
  return options;
}

TEST(TeamScans, TheTeamsSummaryIsTheWholeSetsWhoeverReadWhich) {
  std::vector<RangeMap> frames = roomFrames().reconstruction;
  const std::vector<RangeMap> street = streetFrames(9);
  frames.insert(frames.end(), street.begin(), street.end());
  const ScanSummary whole(frames);
  test::runOnThreadTeam(3, [&](const SlabTeam& team) {
    const ScanSummary mine = scansNumbered(frames, readFirst(frames, team)).summary;
    const ScanSummary told = teamSummary(mine, team);
    EXPECT_EQ(told.scans(), whole.scans());
    EXPECT_EQ(told.readings(), whole.readings());
    EXPECT_EQ(told.points(), whole.points());
    EXPECT_EQ(told.medianRaySpacing(), whole.medianRaySpacing());
    EXPECT_EQ(told.medianSigma(), whole.medianSigma());
    EXPECT_EQ(told.bounds().min(), whole.bounds().min());
    EXPECT_EQ(told.bounds().max(), whole.bounds().max());
    EXPECT_EQ(told.aScene(), whole.aScene());
    EXPECT_EQ(told.colouredScans(), whole.colouredScans());
    EXPECT_LT(mine.scans(), whole.scans());
  });
  // Numbers that are no summary's are refused.
  std::vector<double> numbers = whole.numbers();
  EXPECT_EQ(ScanSummary::fromNumbers(numbers).numbers(), numbers);
  numbers.pop_back();
  EXPECT_THROW(ScanSummary::fromNumbers(numbers), std::invalid_argument);
}

/// The street reconstructed by `processes` that each read their part of the
/// frames, plan, and hold the frames their slab needs (the first needing
/// every frame if `firstNeedsEvery`), with `options`; every process's result
/// and the frames it held.
struct TeamRun {
  std::vector<ReconstructionResult> results;
  std::vector<std::vector<std::size_t>> held;
  std::vector<SharedDataSlab> slabs;
};

TeamRun streetOnTeam(const std::vector<RangeMap>& frames, const ReconstructionOptions& options, int processes,
                     bool firstNeedsEvery) {
  TeamRun run;
  run.results.resize(static_cast<std::size_t>(processes));
  run.held.resize(static_cast<std::size_t>(processes));
  run.slabs.resize(static_cast<std::size_t>(processes));
  test::runOnThreadTeam(processes, [&](const SlabTeam& team) {
    const std::size_t r = static_cast<std::size_t>(team.rank());
    const std::vector<std::size_t> first = readFirst(frames, team);
    const PackedScans read = scansNumbered(frames, first);
    const ScanSummary whole = teamSummary(read.summary, team);
    const ReconstructionSettings resolved = resolveReconstructionSettings(options, whole);
    const TeamScanPlan plan =
        planTeamScans(read, first, frames.size(), resolved, firstNeedsEvery && r == 0, team);
    ASSERT_TRUE(plan.slab);
    run.slabs[r] = *plan.slab;
    run.held[r] = plan.needed;
    PackedScans needed = scansNumbered(frames, plan.needed);
    needed.summary = whole;
    ScansReconstruction made = prepareReconstruction(std::move(needed), resolved, {}, {}, &team, &*plan.slab);
    EXPECT_EQ(made.reconstructor->summary().scans(), frames.size()) << "the team's scans are counted";
    run.results[r] = made.reconstructor->run({}, {}, &team);
  });
  return run;
}

/// Expects each process of `run` to hold fewer than `atMost` of the `frames`
/// and every frame to be held by some process.
void expectFramesHeldInPart(const TeamRun& run, std::size_t frames, double atMost, std::size_t from = 0) {
  std::vector<int> holders(frames, 0);
  for (std::size_t r = 0; r < run.held.size(); ++r) {
    for (std::size_t n : run.held[r]) ++holders.at(n);
    if (r < from) continue;
    EXPECT_LT(static_cast<double>(run.held[r].size()), atMost * static_cast<double>(frames))
        << "process " << r << " holds " << run.held[r].size() << " of " << frames << " frames";
  }
  EXPECT_EQ(std::count(holders.begin(), holders.end(), 0), 0) << "a frame no process holds";
}

TEST(TeamScans, ProcessesThatHoldTheFramesTheirSlabNeedsGiveOneProcesssSurface) {
  const std::vector<RangeMap> frames = streetFrames();
  const ReconstructionOptions options = streetOptions();
  PackedScans all;
  for (const RangeMap& frame : frames) all.add(RangeMap(frame));
  const ReconstructionSettings settings = resolveReconstructionSettings(options, all.summary);
  const ScansReconstruction alone = prepareReconstruction(std::move(all), settings);
  ASSERT_EQ(alone.reconstructor->settings().levels, 1);
  const ReconstructionResult aloneResult = alone.reconstructor->run();
  constexpr int kProcesses = 4;
  const TeamRun run = streetOnTeam(frames, options, kProcesses, /*firstNeedsEvery=*/true);
  EXPECT_EQ(run.held[0].size(), frames.size()) << "the first process needs every frame";
  // Measured: 26, 27 and 18 of the 48 frames.
  expectFramesHeldInPart(run, frames.size(), 0.6, 1);
  // The slabs are those of one process holding every frame.
  test::runOnThreadTeam(kProcesses, [&](const SlabTeam& team) {
    const SharedDataSlab cut = sharedDataSlab(rangeMapsOf(frames), resolveReconstructionSettings(options, ScanSummary(frames)), team);
    const SharedDataSlab& planned = run.slabs[static_cast<std::size_t>(team.rank())];
    EXPECT_EQ(cut.own.begin, planned.own.begin);
    EXPECT_EQ(cut.own.end, planned.own.end);
    EXPECT_EQ(cut.data.begin, planned.data.begin);
    EXPECT_EQ(cut.data.end, planned.data.end);
  });
  const ReconstructionResult& first = run.results[0];
  ASSERT_TRUE(first.levelSet && first.weight);
  ASSERT_EQ(first.levels.size(), aloneResult.levels.size());
  EXPECT_EQ(first.levels[0].iterations, aloneResult.levels[0].iterations);
  EXPECT_EQ(first.levels[0].activeSetVoxels, aloneResult.levels[0].activeSetVoxels);
  std::string why;
  EXPECT_TRUE(test::identical(*aloneResult.levelSet, *first.levelSet, &why)) << why;
  EXPECT_TRUE(test::sameTreeBytes(*aloneResult.levelSet, *first.levelSet)) << "the trees' tiles or nodes differ";
  EXPECT_TRUE(test::identical(*aloneResult.weight, *first.weight, &why)) << why;
  EXPECT_EQ(first.levelSet->metaValue<openvdb::Int32>("levelfuse_scans"), static_cast<int>(frames.size()));
}

TEST(TeamScans, ProcessesThatHoldTheFramesTheirSlabNeedsKeepPiecesOfOneProcesssSurface) {
  const std::vector<RangeMap> frames = streetFrames();
  ReconstructionOptions options = streetOptions();
  const ReconstructionResult alone = Reconstructor(frames, options).run();
  options.keepPieces = true;
  constexpr int kProcesses = 3;
  const TeamRun run = streetOnTeam(frames, options, kProcesses, /*firstNeedsEvery=*/false);
  // Measured: 23, 31 and 22 of the 48 frames.
  expectFramesHeldInPart(run, frames.size(), 0.7);
  std::size_t voxels = 0;
  for (int r = 0; r < kProcesses; ++r) {
    const ReconstructionResult& mine = run.results[static_cast<std::size_t>(r)];
    ASSERT_TRUE(mine.levelSet && mine.weight) << "process " << r;
    const openvdb::FloatGrid::Ptr clipped = test::clippedToSlab(*alone.levelSet, run.slabs[static_cast<std::size_t>(r)].own);
    std::string why;
    EXPECT_TRUE(test::identical(*clipped, *mine.levelSet, &why)) << "process " << r << ": " << why;
    EXPECT_TRUE(test::sameTreeBytes(*clipped, *mine.levelSet)) << "process " << r;
    voxels += mine.levelSet->activeVoxelCount();
  }
  EXPECT_EQ(voxels, alone.levelSet->activeVoxelCount());
}

TEST(TeamScans, ATeamThatDoesNotShareTheDataNeedsEveryScan) {
  // Coarse-to-fine: every process holds the whole data term, and every scan.
  const std::vector<RangeMap> frames = streetFrames(8);
  ReconstructionOptions options = streetOptions();
  options.levels = 2;
  test::runOnThreadTeam(2, [&](const SlabTeam& team) {
    const std::vector<std::size_t> first = readFirst(frames, team);
    const PackedScans read = scansNumbered(frames, first);
    const ScanSummary whole = teamSummary(read.summary, team);
    const TeamScanPlan plan =
        planTeamScans(read, first, frames.size(), resolveReconstructionSettings(options, whole), false, team);
    EXPECT_FALSE(plan.slab);
    EXPECT_EQ(plan.needed.size(), frames.size());
  });
}

}  // namespace
}  // namespace levelfuse
