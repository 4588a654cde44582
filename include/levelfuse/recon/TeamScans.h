// levelfuse: the scans of a team read by the processes that need them.
//
// The processes of a team (levelset/SlabTeam.h, e.g. the ranks of an MPI job)
// that share a reconstruction first read the scans in turn, each a part
// (scan i by process i mod the team's size), and agree on what the settings
// are taken from (teamSummary). Where the team shares the data in slabs
// (recon/SharedData.h), each process then finds, of the scans it read, where
// their windows reach and what their lines of sight can see, and the team
// cuts the slabs from all of it (planTeamScans). A process needs a scan if
// its windows reach the process's slab of the data, or if its lines of sight
// can see the blocks that carving decides there: every other scan leaves its
// slab of the data term and of the initial model as they are, bit for bit.
// Each process then holds, and reads, only the scans it needs.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/levelset/SlabTeam.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/SharedData.h>
#include <levelfuse/scan/PackedRangeMap.h>
#include <levelfuse/scan/ScanSummary.h>

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

namespace levelfuse {

/// Whether the scan numbered `scan` (from 0, in the order of the inputs) is
/// among the part of a team's scans that the process `rank` of `processes`
/// reads first: scan mod processes is rank.
inline bool readFirstBy(std::size_t scan, int rank, int processes) {
  return scan % static_cast<std::size_t>(processes) == static_cast<std::size_t>(rank);
}

/// The summary of every process's scans (`own`, its part), on every process:
/// the whole set's (ScanSummary::add), alike everywhere.
ScanSummary teamSummary(const ScanSummary& own, const SlabTeam& team);

/// Which of a team's scans this process needs, and its slab of the data.
struct TeamScanPlan {
  /// This process's slab of the data, where the team shares the data in slabs.
  std::optional<SharedDataSlab> slab;
  /// The numbers of the scans it needs, in order.
  std::vector<std::size_t> needed;
};

/// What this process of `team` needs of the team's `scanCount` scans, for a
/// reconstruction with the `settings` (those of teamSummary): every
/// scan unless the team shares the data in slabs (sharesDataInSlabs); then
/// the scans whose windows reach its slab of the data or whose lines of sight
/// may see the blocks carving decides there (RangeMap::mayBeSeenIn), or every
/// scan if `needsEvery` (a process that measures the whole surface against
/// every scan). `held` are the scans it read (numbered `numbers`, in order),
/// visited once, `interrupter` asked before each (Interrupted). Every process
/// calls it, with its own part; the slabs are those sharedDataSlab cuts from
/// all the scans.
TeamScanPlan planTeamScans(const PackedScans& held, const std::vector<std::size_t>& numbers, std::size_t scanCount,
                           const ReconstructionSettings& settings, bool needsEvery, const SlabTeam& team,
                           const Interrupter& interrupter = {});

/// The world box in which carving decides blocks for the slab of the data
/// `data`: the data's box `dataVoxels` (the voxels of the leaf nodes the
/// windows reach, ReachedLeaves::voxelBox) cut to the slab and two blocks
/// beyond, grown by a block and half a voxel, on a grid of `voxelSize`.
openvdb::BBoxd carvingBoxOf(const SlabBounds& data, const openvdb::CoordBBox& dataVoxels, double voxelSize);

/// Scans read from a run's inputs, each numbered among all the inputs' scans
/// (from 0, in the order of the inputs), held packed.
struct NumberedScans {
  PackedScans scans;                  ///< held packed, in the order read
  std::vector<std::size_t> numbers;   ///< of each scan held, its number
  std::size_t scanCount = 0;          ///< the scans of all the inputs, read or not
  std::optional<RangeMap> firstScan;  ///< scan 0, if it was read: a scene's preview looks from its camera
};

/// Reads the scans of a run's inputs that `wanted` picks by their number.
using NumberedScanReader = std::function<NumberedScans(const std::function<bool(std::size_t)>& wanted)>;

/// What readTeamScans gives each process of a team.
struct TeamShare {
  NumberedScans held;  ///< the scans it needs, in the order of their numbers
  /// Resolved from every process's scans (teamSummary): alike everywhere.
  ReconstructionSettings settings;
  /// Its slab of the data, where the team shares the data in slabs.
  std::optional<SharedDataSlab> slab;
};

/// The scans this process of `team` needs of a run's inputs, read with
/// `read`: the processes read the scans in turn (readFirstBy), agree on the
/// settings from all of them (teamSummary, resolveReconstructionSettings of
/// `given`), plan which each needs (planTeamScans; every scan if
/// `needsEvery`), let go of those read first that they do not need, and read
/// those they lack. The scans come in the order of their numbers, with the
/// whole team's summary; their samples are let go unless `needsEvery` (only
/// the fit reads them). Throws std::invalid_argument for unusable settings.
TeamShare readTeamScans(const NumberedScanReader& read, const ReconstructionOptions& given, bool needsEvery,
                        const SlabTeam& team, const Interrupter& interrupter = {});

}  // namespace levelfuse
