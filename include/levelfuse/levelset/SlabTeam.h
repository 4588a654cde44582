// levelfuse: the processes that share a sparse field, one slab each
// (SlabField.h), and one step of the field across them.
//
// A team is whatever moves a slab's ghosts between neighbours and combines
// numbers over all slabs: the MPI layer's mpi::RankTeam (mpi/RankTeam.h) for
// the ranks of an MPI job. The library's pipeline (recon/Reconstructor.h)
// steps its slab through this interface and so knows nothing of MPI.
#pragma once

#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/SpeedTerms.h>
#include <levelfuse/levelset/StepTally.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

namespace levelfuse {

class SlabTeam {
 public:
  virtual ~SlabTeam() = default;

  /// This process's place along x (its slab's), from 0, and the team's size.
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// The largest of every process's `value`, on every process.
  virtual double largest(double value) const = 0;
  /// The sum of every process's `count`, on every process.
  virtual std::uint64_t total(std::uint64_t count) const = 0;
  /// The sum of every process's tally (exact: StepTally.h), on every process.
  virtual StepTally sum(const StepTally& tally) const = 0;
  /// Sends the slab's leaves beside each neighbour and takes theirs as its ghosts.
  virtual void refreshGhosts(SlabField& slab) const = 0;
  /// Every process's `leaves` at `root`, handed to `take` one process's at a
  /// time, in rank order: the root holds one process's leaves at once, not
  /// every one's. `take` is called on the root only.
  virtual void gatherEach(PackedLeaves leaves, int root, const std::function<void(PackedLeaves)>& take) const = 0;
  /// Every process's `leaves`, in rank order, at `root`; empty on the others.
  std::vector<PackedLeaves> gather(PackedLeaves leaves, int root) const {
    std::vector<PackedLeaves> all;
    gatherEach(std::move(leaves), root, [&](PackedLeaves piece) { all.push_back(std::move(piece)); });
    return all;
  }
  /// Sends `toEach[r]` to process r (one entry per process, this one's
  /// included) and returns what every process sent to this one, in rank order.
  virtual std::vector<PackedLeaves> exchange(std::vector<PackedLeaves> toEach) const = 0;
};

/// Every process's leaf columns (leafColumns of its own leaves) summed over
/// the team, in order of x: the whole field's, on every process.
std::vector<std::pair<openvdb::Int32, std::size_t>> teamLeafColumns(
    const std::vector<std::pair<openvdb::Int32, std::size_t>>& own, const SlabTeam& team);

/// The team's field on the grid of half the voxel size, this process's slab
/// of it: every process calls it with its own slab. Each slab's level set is
/// refined (refineLevelSet) with fresh ghosts; the finer grid is cut afresh
/// where the refined level set's leaf nodes share out evenly (balancedSlabs
/// of teamLeafColumns), and each process hands the leaves of its refined
/// level set to the processes whose new slabs read them (levelSetReach). The
/// slabs are those of the whole field refined and cut there, bit for bit.
SlabField refineAcrossTeam(SlabField slab, const SlabTeam& team, const SparseFieldOptions& engine);

/// Leaf nodes of a level set packed and sent at once when a team gathers
/// one (gatherLevelSetLeaves): 8.7 MB.
inline constexpr std::size_t kLeavesPerParcel = 4096;

/// Every process's leaves of `piece` whose origin x lies in its slab `own`,
/// put into `whole` at the team's first process (every process calls it,
/// each with its own slab; `whole` is used at the first alone). The first
/// moves its own; each other packs its leaves in parcels of whole columns,
/// at most `leavesPerParcel` leaf nodes each (parcelsOf), and sends them one
/// at a time: neither side holds more than one parcel's bytes beside the
/// grids. `piece` is let go.
void gatherLevelSetLeaves(openvdb::FloatGrid::Ptr& piece, const SlabBounds& own, openvdb::FloatGrid& whole,
                          const SlabTeam& team, std::size_t leavesPerParcel = kLeavesPerParcel);

/// One step of the field the team shares; every process calls it with its
/// own slab. Returns the whole field's report, the same on every process.
template <typename Speed>
StepResult stepSlab(SlabField& slab, const Speed& speed, const SlabTeam& team,
                    double maxDt = std::numeric_limits<double>::infinity()) {
  team.refreshGhosts(slab);
  const double maxSpeed = team.largest(slab.computeRates(speed));
  const double dt = slab.timeStep(maxSpeed, speed.curvatureWeight(), speedStiffness(speed), maxDt);
  return team.sum(slab.applyRates(dt, maxSpeed)).result(slab.voxelSize());
}

}  // namespace levelfuse
