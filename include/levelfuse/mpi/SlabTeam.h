// levelfuse: the processes of an MPI job sharing one sparse field, one slab
// each (levelset/SlabField.h), and a step of the field across them.
//
// Rank r holds the r-th slab along x. A step is bulk-synchronous, as on
// threads: the ranks exchange ghosts with their two neighbours (non-blocking
// point to point), agree on the largest speed (MPI_Allreduce) and so on the
// time step, step their own slabs with TBB, and add their tallies
// (MPI_Allgather, summed in rank order; the sums are exact, so the order does
// not matter). The result is bit-identical to one process's.
#pragma once

#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/SpeedTerms.h>

#include <mpi.h>

#include <cstdint>
#include <limits>
#include <vector>

namespace levelfuse::mpi {

class SlabTeam {
 public:
  /// The ranks of `communicator`; rank r holds the r-th slab along x.
  explicit SlabTeam(MPI_Comm communicator = MPI_COMM_WORLD);

  int rank() const { return mRank; }
  int size() const { return mSize; }
  MPI_Comm communicator() const { return mCommunicator; }

  /// The largest of every rank's `value`, on every rank.
  double largest(double value) const;
  /// The sum of every rank's tally, on every rank.
  StepTally sum(const StepTally& tally) const;
  /// Sends the slab's leaves beside each neighbouring rank and takes theirs
  /// as its ghosts. The slab must be this rank's (its bounds open at the
  /// first and last rank only).
  void refreshGhosts(SlabField& slab) const;
  /// Every rank's `leaves`, in rank order, at `root`; empty on the others.
  std::vector<PackedLeaves> gather(const PackedLeaves& leaves, int root = 0) const;
  /// Bytes of ghosts this rank has sent so far.
  std::uint64_t ghostBytesSent() const { return mGhostBytesSent; }

 private:
  MPI_Comm mCommunicator;
  int mRank = 0;
  int mSize = 1;
  mutable std::uint64_t mGhostBytesSent = 0;
};

/// One step of the field the team shares; every rank calls it with its slab.
/// Returns the whole field's report, the same on every rank.
template <typename Speed>
StepResult step(SlabField& slab, const Speed& speed, const SlabTeam& team,
                double maxDt = std::numeric_limits<double>::infinity()) {
  team.refreshGhosts(slab);
  const double maxSpeed = team.largest(slab.computeRates(speed));
  const double dt = slab.timeStep(maxSpeed, speed.curvatureWeight(), speedStiffness(speed), maxDt);
  return team.sum(slab.applyRates(dt, maxSpeed)).result(slab.voxelSize());
}

}  // namespace levelfuse::mpi
