// levelfuse: the data term shared by a team, slab by slab.

#include <levelfuse/recon/SharedData.h>

#include <levelfuse/recon/FusionSettings.h>
#include <levelfuse/scan/AccumulationCost.h>

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

bool sharesDataInSlabs(const ReconstructionOptions& resolved, const SlabTeam* team) {
  return team && team->size() > 1 && resolved.dataTerm == DataTermSource::kGrids && resolved.levels == 1;
}

SharedDataSlab sharedDataSlab(const RangeMapSequence& maps, const ReconstructionOptions& resolved,
                              const SlabTeam& team) {
  const FusionSettings grids = fusionSettingsOf(resolved);
  const int finest = grids.levels - 1;
  const auto columns = accumulationColumns(maps, grids.levelVoxelSize(finest),
                                           grids.levelForceOptions(finest).dataWindow().reach());
  SharedDataSlab slab;
  slab.own = balancedSlabs(columns, team.size()).at(static_cast<std::size_t>(team.rank()));
  slab.data = dataSlabOf(slab.own);
  std::size_t all = 0, within = 0;
  for (const auto& [x, leaves] : columns) {
    all += leaves;
    if (slab.data.contains(x)) within += leaves;
  }
  slab.share = static_cast<double>(within) / static_cast<double>(all);
  return slab;
}

std::unique_ptr<Fusion> fusionOnTeam(const AccumulationCostOf& costOf, const RangeMapSequence& maps,
                                     const ReconstructionOptions& resolved, Fusion::Keep keep, const SlabTeam* team,
                                     const Interrupter& interrupter) {
  if (!sharesDataInSlabs(resolved, team)) return fusionFor(costOf, resolved, keep);
  const RangeMapSequence asked = [&](const RangeMapVisitor& visit) {
    maps([&](const RangeMap& map) {
      checkInterrupter(interrupter);
      visit(map);
    });
  };
  const SharedDataSlab slab = sharedDataSlab(asked, resolved, *team);
  // The leaves' lists and the grids grow with the leaves the slab's data hold.
  const AccumulationCostOf shareOfCost = [&](double voxelSize, double reach) {
    AccumulationCost cost = costOf(voxelSize, reach);
    cost.leafMarks *= slab.share;
    cost.leaves *= slab.share;
    cost.bytes *= slab.share;
    return cost;
  };
  std::unique_ptr<Fusion> fusion = fusionFor(shareOfCost, resolved, keep);
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

}  // namespace levelfuse
