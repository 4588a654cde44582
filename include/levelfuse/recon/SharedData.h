// levelfuse: the data term shared by a team, slab by slab.
//
// When the processes of a team (levelset/SlabTeam.h, e.g. the ranks of an MPI
// job) share a reconstruction of one grid whose data term comes from grids
// (depth frames, scenes: many scans), each integrates the scans only within
// its slab of x and the voxels its slab reads beyond (dataSlabOf), and makes
// its initial model from that part alone: no process holds the whole data
// term. The slabs are cut before any scan is integrated, where the leaf
// nodes the readings' windows reach share out evenly (accumulationColumns):
// those leaves hold the data term's work and memory, and the surface.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/SlabTeam.h>
#include <levelfuse/recon/Fusion.h>
#include <levelfuse/recon/ReconstructionOptions.h>
#include <levelfuse/scan/AccumulationCost.h>
#include <levelfuse/scan/ForceField.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>

#include <memory>
#include <utility>
#include <vector>

namespace levelfuse {

/// Voxels a slab's data reach past each face it shares with a neighbour. The
/// slab's own leaves of the initial model need to be the whole data's: the
/// linear solution of a slab of the data is, but within
/// kLinearSolutionSlabMargin (17) of the data's faces, and the sparse
/// field's layers read 4 voxels beyond (the layer rule's passes): 21. The
/// evolution reads the data term at the slab's ghosts (a column of leaf
/// nodes, 8 voxels) and around them (subcell positions within a voxel, and
/// the voxels around those): 10. Three columns of leaf nodes.
inline constexpr openvdb::Int32 kSharedDataMargin = 3 * kLeafNodeWidth;

/// The x range of the data the slab `own` reads: kSharedDataMargin past each
/// face it shares with a neighbour.
SlabBounds dataSlabOf(const SlabBounds& own);
/// The slab whose data are `data` (the inverse of dataSlabOf).
SlabBounds ownSlabOf(const SlabBounds& data);

/// Whether a run with the `settings` on `team` shares its data term
/// in slabs: a team of more than one process, the data term from grids, one
/// grid. (Coarse-to-fine runs cut each finer grid afresh as it comes, and
/// keep the whole data term on every process.)
bool sharesDataInSlabs(const ReconstructionSettings& settings, const SlabTeam* team);

/// Whether a run with the `settings` on `team` integrates the data
/// term of each grid but the coarsest within each process's slab of that
/// grid, once the grid is cut (Fusion::deferLevel): a team of more than one
/// process, the data term from grids, coarse to fine. (The coarsest grid's
/// data, whole on every process, make the initial model: a quarter of the
/// next grid's or less.)
bool defersFinerGrids(const ReconstructionSettings& settings, const SlabTeam* team);

/// This process's part of the data of a team that shares them in slabs.
struct SharedDataSlab {
  SlabBounds own;   ///< its slab of the field
  SlabBounds data;  ///< the data it integrates (dataSlabOf)
};

/// Every process's part of the data of a team of `processes` that shares them
/// in slabs, in rank order: x cut where the leaf nodes `reached` (the windows
/// of all the team's maps on the grid of the run) share out evenly
/// (balancedSlabs of their columns). Throws std::invalid_argument if they
/// span fewer columns of leaf nodes than the team has processes
/// (balancedSlabs).
std::vector<SharedDataSlab> sharedDataSlabs(const ReachedLeaves& reached, int processes);

/// This process's part of `team`'s data (sharedDataSlabs), the leaves
/// reached found from `maps` on the grid of the `settings`: alike on
/// every process that visits the same maps.
SharedDataSlab sharedDataSlab(const RangeMapSequence& maps, const ReconstructionSettings& settings,
                              const SlabTeam& team);

/// The leaf nodes the windows reach on the grid of the `settings`, to
/// be added to (ReachedLeaves): the grid's finest voxel size and the window's reach.
ReachedLeaves reachedLeavesOf(const ReconstructionSettings& settings);

/// The world x range of the voxels of `slab` (centred on multiples of
/// `voxelSize`), from -HUGE_VAL to HUGE_VAL where it is unbounded.
std::pair<double, double> worldRangeOf(const SlabBounds& slab, double voxelSize);

/// An empty fusion of the `settings`' grids for the maps whose cost
/// `costWithin` finds (fusionFor), keeping `keep` of them: on a `team` that
/// shares the data in slabs (sharesDataInSlabs), of this process's slab of
/// the data (Fusion::restrictToSlab), whose memory is checked for the data
/// within it alone; on a team that defers the finer grids (defersFinerGrids),
/// without them. The slab is `cut` if given (found beforehand, e.g. by
/// planTeamScans), else found from `maps` (sharedDataSlab), which are then
/// visited once, with `interrupter` asked before each (Interrupted).
std::unique_ptr<Fusion> fusionOnTeam(const AccumulationCostWithin& costWithin, const RangeMapSequence& maps,
                                     const ReconstructionSettings& settings, Fusion::Keep keep, const SlabTeam* team,
                                     const Interrupter& interrupter = {}, const SharedDataSlab* cut = nullptr);

/// The box of every process's box `own` (an empty box for none), on every process.
openvdb::CoordBBox teamBox(const openvdb::CoordBBox& own, const SlabTeam& team);

/// This process's slab `data` of `team`'s data, as the linear solution of it
/// asks (linearSolutionSlabField): the team agrees on the box of the whole data.
SlabOfTheData slabOfTheData(const SlabBounds& data, const SlabTeam& team);

/// `scans` integrated into a fusion for them (fusionFor), each map unpacked
/// once and then kept packed by the fusion. `integrated`, if
/// set, is told after each map how many of how many are in; Interrupted if
/// `interrupter` asks to stop between maps.
/// On a `team` that shares the data in slabs (recon/SharedData.h), the
/// fusion holds this process's slab of the data alone (restrictToSlab), and
/// only the team's run() reconstructs from it: the slab `cut` when it is
/// given (planTeamScans), found from `scans` otherwise. The fusion's summary
/// is `scans`' (adoptSummary): the team's, where this process holds a part.
std::unique_ptr<Fusion> fusePackedScans(PackedScans scans, const ReconstructionSettings& settings,
                                        const std::function<void(std::size_t, std::size_t)>& integrated = {},
                                        const Interrupter& interrupter = {}, const SlabTeam* team = nullptr,
                                        const SharedDataSlab* cut = nullptr);

}  // namespace levelfuse
