// One slab of the data (recon/SharedData.h): the processes of a team each
// integrate the scans within their slab and the voxels their slab reads
// beyond, and make their slab of the initial model from those data alone
// (linearSolutionSlabField). It must be the whole data's, bit for bit, where
// carving closes unseen space across the cuts too.

#include "RoomFrames.h"
#include "support/TestSupport.h"
#include "support/ThreadTeam.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/recon/SharedData.h>
#include <levelfuse/scan/DataTermGrids.h>
#include <levelfuse/scan/ForceField.h>
#include <levelfuse/synth/Synth.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Coord;
using openvdb::Vec3d;

struct Scene {
  std::vector<RangeMap> maps;
  double voxelSize;
  double epsilon;
};

/// Two spheres seen from one side only: the shadows behind them, which
/// carving closes, run across every cut along x.
Scene spheresFromOneSide() {
  const shapes::Sphere left{Vec3d(-0.45, 0.05, 0.0), 0.4}, right{Vec3d(0.5, -0.1, 0.1), 0.3};
  const auto both = [&](const Vec3d& x) { return std::min(left(x), right(x)); };
  Scene scene{{}, 0.02, 0.02};
  synth::Noise noise;
  noise.gaussianSigma = 0.004;
  int seed = 1;
  for (const Vec3d& direction : {Vec3d(0.15, 0.05, -1.0), Vec3d(-0.2, 0.1, -1.0), Vec3d(0.0, -0.25, -1.0)}) {
    noise.seed = static_cast<std::uint64_t>(seed++);
    scene.maps.push_back(synth::renderDistanceFunction(
        both, synth::orthographicView(direction.unit(), Vec3d(0.0), 2.2, 110), noise, 0.004));
  }
  return scene;
}

/// Depth frames of a room, every surface seen from one side.
Scene room() { return Scene{roomFrames().reconstruction, 0.02, 0.01}; }

ForceFieldOptions optionsOf(const Scene& scene) {
  ForceFieldOptions options;
  options.epsilon = scene.epsilon;
  options.positionVariance = scene.voxelSize * scene.voxelSize / 120.0;
  return options;
}

/// The scene's data term accumulated within `data` alone (all of it by default).
DataTermGrids dataOf(const Scene& scene, const SlabBounds& data = {}) {
  const ForceFieldOptions options = optionsOf(scene);
  DataTermGrids grids(scene.voxelSize, options.dataWindow(), options.positionVariance);
  if (data.hasLower() || data.hasHigher()) grids.restrictToSlab(data.begin, data.end);
  for (const RangeMap& m : scene.maps) grids.integrate(m);
  return grids;
}

/// The slab `own` of the linear solution made of the data within `data`
/// alone, as a process of a team whose whole data reach `wholeBlocks` makes it.
SlabField slabOfTheLinearSolution(const Scene& scene, const SlabBounds& data, const SlabBounds& own,
                                  const openvdb::CoordBBox& wholeBlocks) {
  const DataTermGrids grids = dataOf(scene, data);
  const SlabOfTheData slab{data, [&](const openvdb::CoordBBox&) { return wholeBlocks; }};
  return linearSolutionSlabField(AccumulatedField{grids.gGrid(), grids.weightGrid(), 0}, rangeMapsOf(scene.maps),
                                 optionsOf(scene).dataWindow().reach(), LinearBand::kZeroCrossings, slab, own);
}

/// The voxels of the slabs' own leaves (x in `own`) whose value or activity differ.
std::size_t ownVoxelsThatDiffer(const SlabField& a, const SlabField& b, const SlabBounds& own) {
  std::size_t differ = 0;
  const auto compare = [&](const openvdb::FloatGrid& x, const openvdb::FloatGrid& y) {
    const openvdb::FloatGrid::ConstAccessor other = y.getConstAccessor();
    for (auto it = x.cbeginValueOn(); it; ++it)
      if (own.contains(it.getCoord().x()))
        differ += !other.isValueOn(it.getCoord()) || other.getValue(it.getCoord()) != *it;
  };
  compare(a.grid(), b.grid());
  compare(b.grid(), a.grid());
  return differ;
}

/// Every slab of 4 columns of leaf nodes begun every `step` voxels, and both
/// halves at each of those cuts, made of its data, is the whole's.
void expectSlabsOfTheDataMakeTheWholesSlabs(const Scene& scene, openvdb::Int32 step) {
  const DataTermGrids wholeData = dataOf(scene);
  const openvdb::FloatGrid::Ptr g = wholeData.gGrid();
  openvdb::CoordBBox wholeBlocks;
  for (auto leaf = g->tree().cbeginLeaf(); leaf; ++leaf) wholeBlocks.expand(leaf->origin() >> 3);
  const SparseField whole = linearSolutionField(AccumulatedField{g, wholeData.weightGrid(), 0}, scene.maps,
                                                optionsOf(scene).dataWindow().reach(), LinearBand::kZeroCrossings);
  // Each made of its data (dataSlabOf), and of the data within the slab alone.
  const openvdb::Int32 first = wholeBlocks.min().x() * 8, last = wholeBlocks.max().x() * 8;
  int slabs = 0, slabsThatNeedTheMargin = 0;
  for (openvdb::Int32 begin = first - 8; begin <= last; begin += step) {
    for (const SlabBounds& own : {SlabBounds{begin, begin + 32}, SlabBounds{-SlabBounds::kUnbounded, begin},
                                  SlabBounds{begin, SlabBounds::kUnbounded}}) {
      const SlabField wholes = SlabField::fromField(whole, own);
      const SlabField shared = slabOfTheLinearSolution(scene, dataSlabOf(own), own, wholeBlocks);
      const std::string where = "slab [" + std::to_string(own.begin) + ", " + std::to_string(own.end) + ")";
      EXPECT_EQ(ownVoxelsThatDiffer(wholes, shared, own), 0u) << where;
      EXPECT_EQ(wholes.stats().activeSetVoxels, shared.stats().activeSetVoxels) << where;
      EXPECT_EQ(wholes.stats().bandVoxels, shared.stats().bandVoxels) << where;
      EXPECT_EQ(wholes.stats().leafNodes, shared.stats().leafNodes) << where;
      const SlabField withoutMargin = slabOfTheLinearSolution(scene, own, own, wholeBlocks);
      slabsThatNeedTheMargin += ownVoxelsThatDiffer(wholes, withoutMargin, own) > 0;
      ++slabs;
    }
  }
  EXPECT_GT(slabs, 20);
  // Without the margin, slabs differ from the whole's: the test sees a margin
  // too small. (Here the differences reach no deeper than a column of leaf
  // nodes: margins of one to three columns pass too; kSharedDataMargin is
  // what the rules that make the initial model can reach.)
  EXPECT_GT(slabsThatNeedTheMargin, slabs / 4) << "of " << slabs;
}

TEST(SharedData, SpheresSeenFromOneSideMakeTheWholesSlabsOfTheInitialModel) {
  expectSlabsOfTheDataMakeTheWholesSlabs(spheresFromOneSide(), 8);
}

TEST(SharedData, ARoomSeenFromWithinMakesTheWholesSlabsOfTheInitialModel) {
  expectSlabsOfTheDataMakeTheWholesSlabs(room(), 24);
}

TEST(SharedData, ASlabBeyondTheDataIsEmpty) {
  // Every process of a team makes its slab, data or none.
  const Scene scene = spheresFromOneSide();
  const openvdb::CoordBBox wholeBlocks(Coord(-7, -7, -7), Coord(7, 7, 7));
  const SlabBounds own{4000, 4032};
  const SlabField far = slabOfTheLinearSolution(scene, dataSlabOf(own), own, wholeBlocks);
  EXPECT_EQ(far.stats().activeSetVoxels, 0u);
  EXPECT_EQ(far.stats().leafNodes, 0u);
}

TEST(SharedData, CuttingTheSlabsStopsWhenAsked) {
  // The pass over the frames that cuts the slabs, before any is integrated,
  // asks the interrupter before each frame.
  const std::vector<RangeMap> frames = roomFrames().reconstruction;
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.dataTerm = DataTermSource::kGrids;
  const ReconstructionSettings resolved = resolveReconstructionSettings(options, ScanSummary(frames));
  std::vector<int> asked(2, 0);
  EXPECT_THROW(test::runOnThreadTeam(2,
                                     [&](const SlabTeam& team) {
                                       int& mine = asked[static_cast<std::size_t>(team.rank())];
                                       fusionOnTeam(accumulationCostWithin(rangeMapsOf(frames)), rangeMapsOf(frames),
                                                    resolved, Fusion::Keep::kNothing, &team,
                                                    [&mine] { return ++mine > 3; });
                                     }),
               Interrupted);
  EXPECT_EQ(asked[0], 4);
  EXPECT_EQ(asked[1], 4);
}

TEST(SharedData, TheDataOfASlabReachTheMarginPastEachCut) {
  const SlabBounds own{-64, 96};
  EXPECT_EQ(dataSlabOf(own).begin, -64 - kSharedDataMargin);
  EXPECT_EQ(dataSlabOf(own).end, 96 + kSharedDataMargin);
  const SlabBounds first{-SlabBounds::kUnbounded, 96};
  EXPECT_FALSE(dataSlabOf(first).hasLower());
  for (const SlabBounds& slab : {own, first, SlabBounds{}, SlabBounds{8, SlabBounds::kUnbounded}}) {
    EXPECT_EQ(ownSlabOf(dataSlabOf(slab)).begin, slab.begin);
    EXPECT_EQ(ownSlabOf(dataSlabOf(slab)).end, slab.end);
  }
}

}  // namespace
}  // namespace levelfuse
