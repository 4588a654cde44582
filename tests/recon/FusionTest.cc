// Range maps fused one at a time: the batch result, answers at any time, and
// the maps released as soon as they are integrated.

#include "RoomFrames.h"

#include <levelfuse/recon/Fusion.h>
#include <levelfuse/recon/Reconstructor.h>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <memory>
#include <string>
#include <vector>

namespace levelfuse {
namespace {

/// The same active voxels with the same values, bit for bit.
void expectSameGrid(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  ASSERT_EQ(a.activeVoxelCount(), b.activeVoxelCount());
  openvdb::FloatGrid::ConstAccessor other = b.getConstAccessor();
  for (auto it = a.cbeginValueOn(); it; ++it) {
    ASSERT_TRUE(other.isValueOn(it.getCoord())) << it.getCoord();
    ASSERT_EQ(*it, other.getValue(it.getCoord())) << it.getCoord();
  }
}

/// A fusion on a 4 cm grid with the batch reconstructor's settings for these frames.
FusionSettings settingsFor(const Reconstructor& batch) {
  FusionSettings settings;
  settings.voxelSize = batch.settings().voxelSize;
  settings.levels = batch.settings().levels;
  settings.epsilon = batch.settings().epsilon;
  return settings;
}

ReconstructionOptions roomOptions(int levels) {
  ReconstructionOptions options;
  options.voxelSize = 0.04;
  options.levels = levels;
  options.dataTerm = DataTermSource::kGrids;
  return options;
}

TEST(Fusion, FrameByFrameGivesWhatTheFramesTogetherGive) {
  const RoomFrames frames = roomFrames();
  for (const int levels : {1, 2}) {
    const Reconstructor batch(frames.reconstruction, roomOptions(levels));
    Fusion fusion(settingsFor(batch));
    for (const RangeMap& frame : frames.reconstruction) {
      auto passing = std::make_unique<RangeMap>(frame);  // read, integrated, released
      fusion.integrate(*passing);
    }
    EXPECT_EQ(fusion.scanCount(), frames.reconstruction.size());
    ReconstructionOptions derived;  // the rest derived from the fusion's summary, as from the frames
    const Reconstructor streamed(fusion, derived);
    EXPECT_EQ(streamed.settings().beta, batch.settings().beta);
    EXPECT_EQ(streamed.settings().dataTerm, DataTermSource::kGrids);
    EXPECT_TRUE(streamed.maps().empty());
    const ReconstructionResult expected = batch.run();
    const ReconstructionResult got = reconstruct(fusion);
    expectSameGrid(*got.levelSet, *expected.levelSet);
    expectSameGrid(*got.weight, *expected.weight);
    ASSERT_EQ(got.levels.size(), expected.levels.size());
    for (std::size_t l = 0; l < got.levels.size(); ++l) EXPECT_EQ(got.levels[l].iterations, expected.levels[l].iterations);
    // The linear solution: the finest grid's, carved by the packed frames.
    const DataTermGrids& finest = fusion.dataTerm(levels - 1);
    const openvdb::FloatGrid::Ptr fromMaps =
        linearSolutionField(AccumulatedField{finest.gGrid(), finest.weightGrid(), 0}, frames.reconstruction,
                            finest.window().reach(), LinearBand::kZeroCrossings)
            .toLevelSet(3.0);
    expectSameGrid(*fusion.linearSolution(), *fromMaps);
    expectSameGrid(*streamed.linearSolution(), *fromMaps);
    // The maps moved out for the fit, once the grids may go.
    const std::size_t count = fusion.scanCount();
    const PackedScans taken = fusion.takeScans();
    EXPECT_EQ(taken.maps.size(), count);
    EXPECT_EQ(taken.summary.scans(), count);
    EXPECT_EQ(fusion.scanCount(), 0u);
    std::size_t visited = 0;
    taken.unpacked()([&](const RangeMap& m) { EXPECT_EQ(m.name(), frames.reconstruction[visited++].name()); });
    EXPECT_EQ(visited, count);
  }
}

TEST(Fusion, AnswersAtAnyTimeAsFramesKeepComing) {
  const RoomFrames frames = roomFrames();
  const Reconstructor batch(frames.reconstruction, roomOptions(1));
  Fusion growing(settingsFor(batch));
  Fusion firstHalf(settingsFor(batch));
  const std::size_t half = frames.reconstruction.size() / 2;
  for (std::size_t i = 0; i < half; ++i) {
    growing.integrate(frames.reconstruction[i]);
    firstHalf.integrate(frames.reconstruction[i]);
  }
  const openvdb::FloatGrid::Ptr early = growing.linearSolution();
  expectSameGrid(*early, *firstHalf.linearSolution());
  const std::size_t evaluations = growing.dataTerm(0).evaluations();
  EXPECT_NO_THROW(reconstruct(growing));
  EXPECT_EQ(growing.dataTerm(0).evaluations(), evaluations);  // answering integrated nothing again
  for (std::size_t i = half; i < frames.reconstruction.size(); ++i) growing.integrate(frames.reconstruction[i]);
  Fusion all(settingsFor(batch));
  for (const RangeMap& frame : frames.reconstruction) all.integrate(frame);
  const openvdb::FloatGrid::Ptr later = growing.linearSolution();
  expectSameGrid(*later, *all.linearSolution());
  EXPECT_GT(later->activeVoxelCount(), early->activeVoxelCount());  // the second half saw more of the room
}

TEST(Fusion, AnswersFromKeptCarvingVotesAreThoseCarvedFromScratch) {
  const RoomFrames frames = roomFrames();
  const Reconstructor batch(frames.reconstruction, roomOptions(1));
  FusionSettings settings = settingsFor(batch);
  settings.voxelSize = 0.02;  // blocks of 16 cm: frames keep reaching new ones
  ASSERT_TRUE(settings.keepCarvingVotes);
  Fusion growing(settings);
  settings.keepCarvingVotes = false;
  Fusion fromScratch(settings);
  for (std::size_t i = 0; i < frames.reconstruction.size(); ++i) {
    growing.integrate(frames.reconstruction[i]);
    fromScratch.integrate(frames.reconstruction[i]);
    if (i == 3) {
      // An answer stopped while carving loses the votes it took out; the next one asks for them again.
      int asked = 0;
      EXPECT_THROW(growing.linearSolution("surface", [&] { return ++asked > 3; }), Interrupted);
    }
    expectSameGrid(*growing.linearSolution(), *fromScratch.linearSolution());
    EXPECT_GT(growing.memoryBytes(), fromScratch.memoryBytes()) << "after frame " << i;  // the votes kept
  }
}

TEST(Fusion, PackedMapsIntegratedTogetherGiveWhatTheyGiveOneAtATime) {
  const RoomFrames frames = roomFrames();
  const Reconstructor batch(frames.reconstruction, roomOptions(1));
  Fusion oneAtATime(settingsFor(batch));
  for (const RangeMap& frame : frames.reconstruction) oneAtATime.integrate(PackedRangeMap(RangeMap(frame)));
  const openvdb::FloatGrid::Ptr expected = oneAtATime.linearSolution();
  for (const int threads : {1, 2, 5}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    std::vector<PackedRangeMap> packed;
    for (const RangeMap& frame : frames.reconstruction) packed.emplace_back(RangeMap(frame));
    Fusion together(settingsFor(batch));
    std::vector<std::size_t> told;
    together.integrate(std::move(packed), [&](std::size_t done, std::size_t of) {
      EXPECT_EQ(of, frames.reconstruction.size());
      told.push_back(done);
    });
    ASSERT_EQ(told.size(), frames.reconstruction.size()) << threads;
    for (std::size_t i = 0; i < told.size(); ++i) EXPECT_EQ(told[i], i + 1);
    expectSameGrid(*together.linearSolution(), *expected);
    // Kept packed, in order, and visited in order a few at a time.
    std::vector<std::string> names;
    together.scans()([&](const RangeMap& m) { names.push_back(m.name()); });
    ASSERT_EQ(names.size(), frames.reconstruction.size()) << threads;
    for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(names[i], frames.reconstruction[i].name()) << threads;
  }
}

TEST(Fusion, PackedMapsIntegratedTogetherStopWhenAskedAndKeepWhatIsIn) {
  const RoomFrames frames = roomFrames();
  const Reconstructor batch(frames.reconstruction, roomOptions(1));
  std::vector<PackedRangeMap> packed;
  for (const RangeMap& frame : frames.reconstruction) packed.emplace_back(RangeMap(frame));
  Fusion fusion(settingsFor(batch));
  std::size_t in = 0;
  EXPECT_THROW(fusion.integrate(
                   std::move(packed), [&](std::size_t done, std::size_t) { in = done; },
                   [&] { return in == 3; }),
               Interrupted);
  EXPECT_EQ(fusion.scanCount(), 3u);
  std::size_t kept = 0;
  fusion.scans()([&](const RangeMap& m) { EXPECT_EQ(m.name(), frames.reconstruction[kept++].name()); });
  EXPECT_EQ(kept, 3u);
}

TEST(Fusion, RefusesWhatItCannotUse) {
  const RoomFrames frames = roomFrames();
  FusionSettings settings;
  settings.voxelSize = 0.04;
  settings.epsilon = 0.01;
  for (const auto& spoil : std::vector<void (*)(FusionSettings&)>{
           [](FusionSettings& s) { s.voxelSize = 0.0; }, [](FusionSettings& s) { s.voxelSize = 1e-9; },
           [](FusionSettings& s) { s.levels = 0; }, [](FusionSettings& s) { s.levels = 13; },
           [](FusionSettings& s) { s.epsilon = 0.0; }, [](FusionSettings& s) { s.epsilon = std::nan(""); }}) {
    FusionSettings bad = settings;
    spoil(bad);
    EXPECT_THROW(Fusion{bad}, std::invalid_argument);
  }
  Fusion fusion(settings);
  EXPECT_THROW(fusion.linearSolution(), std::invalid_argument);  // no frame yet
  EXPECT_THROW(Reconstructor{fusion}, std::invalid_argument);
  fusion.integrate(frames.reconstruction[0]);
  ReconstructionOptions other;
  other.voxelSize = 0.02;
  EXPECT_THROW(Reconstructor(fusion, other), std::invalid_argument);  // the grids are fixed
  other = ReconstructionOptions();
  other.dataTerm = DataTermSource::kPerMap;
  EXPECT_THROW(Reconstructor(fusion, other), std::invalid_argument);  // the maps are packed away
  EXPECT_THROW(Reconstructor(fusion).dataTermGrids(0), std::invalid_argument);
  Fusion keepsNothing(settings, Fusion::Keep::kNothing);
  keepsNothing.integrate(frames.reconstruction[0]);
  EXPECT_THROW(keepsNothing.linearSolution(), std::invalid_argument);  // nothing to carve with
  const std::vector<RangeMap> handedIn{frames.reconstruction[0]};
  EXPECT_NO_THROW(keepsNothing.linearSolutionField(0, LinearBand::kZeroCrossings, {}, {}, rangeMapsOf(handedIn)));
}

}  // namespace
}  // namespace levelfuse
