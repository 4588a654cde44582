// levelfuse: the data term shared by a team, slab by slab.

#include <levelfuse/recon/SharedData.h>

#include <levelfuse/recon/FusionSettings.h>
#include <levelfuse/scan/AccumulationCost.h>

#include <cmath>

namespace levelfuse {

SlabBounds dataSlabOf(const SlabBounds& own) {
  SlabBounds data = own;
  if (own.hasLower()) data.begin -= kSharedDataMargin;
  if (own.hasHigher()) data.end += kSharedDataMargin;
  return data;
}

SlabBounds ownSlabOf(const SlabBounds& data) {
  SlabBounds own = data;
  if (data.hasLower()) own.begin += kSharedDataMargin;
  if (data.hasHigher()) own.end -= kSharedDataMargin;
  return own;
}

bool sharesDataInSlabs(const ReconstructionSettings& settings, const SlabTeam* team) {
  return team && team->size() > 1 && settings.dataTerm == DataTermSource::kGrids && settings.levels == 1;
}

bool defersFinerGrids(const ReconstructionSettings& settings, const SlabTeam* team) {
  return team && team->size() > 1 && settings.dataTerm == DataTermSource::kGrids && settings.levels > 1;
}

ReachedLeaves reachedLeavesOf(const ReconstructionSettings& settings) {
  const FusionSettings grids = fusionSettingsOf(settings);
  const int finest = grids.levels - 1;
  return ReachedLeaves(grids.levelVoxelSize(finest), grids.levelForceOptions(finest).dataWindow().reach());
}

std::vector<SharedDataSlab> sharedDataSlabs(const ReachedLeaves& reached, int processes) {
  std::vector<SharedDataSlab> slabs;
  for (const SlabBounds& own : balancedSlabs(reached.columns(), processes)) slabs.push_back({own, dataSlabOf(own)});
  return slabs;
}

SharedDataSlab sharedDataSlab(const RangeMapSequence& maps, const ReconstructionSettings& settings,
                              const SlabTeam& team) {
  ReachedLeaves reached = reachedLeavesOf(settings);
  maps([&](const RangeMap& map) { reached.add(map); });
  return sharedDataSlabs(reached, team.size()).at(static_cast<std::size_t>(team.rank()));
}

std::pair<double, double> worldRangeOf(const SlabBounds& slab, double voxelSize) {
  // Voxel x spans x - 1/2 to x + 1/2 voxels.
  return {slab.hasLower() ? (slab.begin - 0.5) * voxelSize : -HUGE_VAL,
          slab.hasHigher() ? (slab.end - 0.5) * voxelSize : HUGE_VAL};
}

std::unique_ptr<Fusion> fusionOnTeam(const AccumulationCostWithin& costWithin, const RangeMapSequence& maps,
                                     const ReconstructionSettings& settings, Fusion::Keep keep, const SlabTeam* team,
                                     const Interrupter& interrupter, const SharedDataSlab* cut) {
  if (!sharesDataInSlabs(settings, team))
    return fusionFor(overAllOfX(costWithin), settings, keep, defersFinerGrids(settings, team));
  const RangeMapSequence asked = [&](const RangeMapVisitor& visit) {
    maps([&](const RangeMap& map) {
      checkInterrupter(interrupter);
      visit(map);
    });
  };
  const SharedDataSlab slab = cut ? *cut : sharedDataSlab(asked, settings, *team);
  // The leaves' lists and the grids grow with the data within the slab.
  const auto [xMin, xMax] = worldRangeOf(slab.data, settings.voxelSize);
  const AccumulationCostOf slabCost = [&, xMin = xMin, xMax = xMax](double voxelSize, double reach) {
    return costWithin(voxelSize, reach, xMin, xMax);
  };
  std::unique_ptr<Fusion> fusion = fusionFor(slabCost, settings, keep);
  fusion->restrictToSlab(slab.data);
  return fusion;
}

openvdb::CoordBBox teamBox(const openvdb::CoordBBox& own, const SlabTeam& team) {
  // The largest of each bound, and of each bound negated for the smallest:
  // an empty box (min above max) takes part in neither.
  openvdb::CoordBBox box;
  for (int axis = 0; axis < 3; ++axis) {
    box.min()[axis] = static_cast<openvdb::Int32>(-team.largest(-static_cast<double>(own.min()[axis])));
    box.max()[axis] = static_cast<openvdb::Int32>(team.largest(static_cast<double>(own.max()[axis])));
  }
  return box;
}

SlabOfTheData slabOfTheData(const SlabBounds& data, const SlabTeam& team) {
  return SlabOfTheData{data, [&team](const openvdb::CoordBBox& own) { return teamBox(own, team); }};
}

std::unique_ptr<Fusion> fusePackedScans(PackedScans scans, const ReconstructionSettings& settings,
                                        const std::function<void(std::size_t, std::size_t)>& integrated,
                                        const Interrupter& interrupter, const SlabTeam* team,
                                        const SharedDataSlab* cut) {
  std::unique_ptr<Fusion> fusion = fusionOnTeam(accumulationCostWithin(scans), scans.unpacked(), settings,
                                                Fusion::Keep::kPacked, team, interrupter, cut);
  fusion->integrate(std::move(scans.maps), integrated, interrupter);
  fusion->adoptSummary(std::move(scans.summary));
  return fusion;
}

}  // namespace levelfuse
