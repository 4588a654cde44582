// levelfuse: the ranks of an MPI communicator as a team sharing one sparse
// field, one slab each (levelset/SlabTeam.h).
//
// Rank r holds the r-th slab along x. A step (stepSlab) is bulk-synchronous,
// as on threads: the ranks exchange ghosts with their two neighbours
// (non-blocking point to point), agree on the largest speed (MPI_Allreduce)
// and so on the time step, step their own slabs with TBB, and add their
// tallies (MPI_Allgather, summed in rank order; the sums are exact, so the
// order does not matter). The result is bit-identical to one process's.
#pragma once

#include <levelfuse/levelset/SlabTeam.h>

#include <mpi.h>

#include <cstdint>
#include <vector>

namespace levelfuse::mpi {

class RankTeam : public SlabTeam {
 public:
  /// The ranks of `communicator`; rank r holds the r-th slab along x.
  explicit RankTeam(MPI_Comm communicator = MPI_COMM_WORLD);

  int rank() const override { return mRank; }
  int size() const override { return mSize; }
  MPI_Comm communicator() const { return mCommunicator; }

  double largest(double value) const override;
  std::uint64_t total(std::uint64_t count) const override;
  StepTally sum(const StepTally& tally) const override;
  /// The slab must be this rank's (its bounds open at the first and last rank only).
  void refreshGhosts(SlabField& slab) const override;
  /// The root receives from one rank at a time; the others wait for it to take theirs.
  void gatherEach(PackedLeaves leaves, int root, const std::function<void(PackedLeaves)>& take) const override;
  /// Sizes by MPI_Alltoall, then the bytes by non-blocking point to point.
  std::vector<PackedLeaves> exchange(std::vector<PackedLeaves> toEach) const override;
  /// Bytes of ghosts this rank has sent so far.
  std::uint64_t ghostBytesSent() const { return mGhostBytesSent; }

 private:
  MPI_Comm mCommunicator;
  int mRank = 0;
  int mSize = 1;
  mutable std::uint64_t mGhostBytesSent = 0;
};

}  // namespace levelfuse::mpi
