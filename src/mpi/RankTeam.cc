// levelfuse: the collective operations of a sparse field shared by MPI ranks.

#include <levelfuse/mpi/RankTeam.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace levelfuse::mpi {

namespace {

/// MPI counts are ints: bytes move in pieces of at most 1 GiB.
constexpr std::size_t kPieceBytes = std::size_t(1) << 30;
enum Tag : int { kSizeTag = 1, kLeavesTag = 2 };

int pieceCount(std::size_t bytes, std::size_t offset) {
  return static_cast<int>(std::min(kPieceBytes, bytes - offset));
}

void postSend(const PackedLeaves& data, int peer, MPI_Comm comm, std::vector<MPI_Request>& requests) {
  for (std::size_t at = 0; at < data.size(); at += kPieceBytes) {
    requests.emplace_back();
    MPI_Isend(data.data() + at, pieceCount(data.size(), at), MPI_BYTE, peer, kLeavesTag, comm, &requests.back());
  }
}

/// `data` must have the size the peer sends.
void postReceive(PackedLeaves& data, int peer, MPI_Comm comm, std::vector<MPI_Request>& requests) {
  for (std::size_t at = 0; at < data.size(); at += kPieceBytes) {
    requests.emplace_back();
    MPI_Irecv(data.data() + at, pieceCount(data.size(), at), MPI_BYTE, peer, kLeavesTag, comm, &requests.back());
  }
}

void waitAll(std::vector<MPI_Request>& requests) {
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  requests.clear();
}

}  // namespace

RankTeam::RankTeam(MPI_Comm communicator) : mCommunicator(communicator) {
  MPI_Comm_rank(mCommunicator, &mRank);
  MPI_Comm_size(mCommunicator, &mSize);
}

double RankTeam::largest(double value) const {
  double out = value;
  MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, mCommunicator);
  return out;
}

std::uint64_t RankTeam::total(std::uint64_t count) const {
  std::uint64_t out = count;
  MPI_Allreduce(&count, &out, 1, MPI_UINT64_T, MPI_SUM, mCommunicator);
  return out;
}

StepTally RankTeam::sum(const StepTally& tally) const {
  std::vector<StepTally> all(static_cast<std::size_t>(mSize));
  MPI_Allgather(&tally, sizeof(StepTally), MPI_BYTE, all.data(), sizeof(StepTally), MPI_BYTE, mCommunicator);
  StepTally total;
  for (const StepTally& t : all) total += t;
  return total;
}

void RankTeam::refreshGhosts(SlabField& slab) const {
  const bool lowerOpen = !slab.bounds().hasLower();
  const bool higherOpen = !slab.bounds().hasHigher();
  if (lowerOpen != (mRank == 0) || higherOpen != (mRank == mSize - 1))
    throw std::logic_error("RankTeam::refreshGhosts: rank " + std::to_string(mRank) + " of " +
                           std::to_string(mSize) + " holds a slab [" + std::to_string(slab.bounds().begin) + ", " +
                           std::to_string(slab.bounds().end) +
                           ") that is not its place in the order along x (only the first rank's begins, and the "
                           "last rank's ends, at infinity)");
  const int lower = mRank - 1, higher = mRank + 1;
  const PackedLeaves toLower = slab.ghostsFor(SlabSide::kLower);
  const PackedLeaves toHigher = slab.ghostsFor(SlabSide::kHigher);

  // First the sizes, then the leaves.
  std::uint64_t sizeToLower = toLower.size(), sizeToHigher = toHigher.size();
  std::uint64_t sizeFromLower = 0, sizeFromHigher = 0;
  std::vector<MPI_Request> requests;
  const auto exchangeSize = [&](std::uint64_t& from, std::uint64_t& to, int peer) {
    requests.resize(requests.size() + 2);
    MPI_Irecv(&from, 1, MPI_UINT64_T, peer, kSizeTag, mCommunicator, &requests[requests.size() - 2]);
    MPI_Isend(&to, 1, MPI_UINT64_T, peer, kSizeTag, mCommunicator, &requests.back());
  };
  if (!lowerOpen) exchangeSize(sizeFromLower, sizeToLower, lower);
  if (!higherOpen) exchangeSize(sizeFromHigher, sizeToHigher, higher);
  waitAll(requests);

  PackedLeaves fromLower(sizeFromLower), fromHigher(sizeFromHigher);
  if (!lowerOpen) {
    postReceive(fromLower, lower, mCommunicator, requests);
    postSend(toLower, lower, mCommunicator, requests);
  }
  if (!higherOpen) {
    postReceive(fromHigher, higher, mCommunicator, requests);
    postSend(toHigher, higher, mCommunicator, requests);
  }
  waitAll(requests);
  mGhostBytesSent += sizeToLower + sizeToHigher;
  slab.acceptGhosts(SlabSide::kLower, fromLower);
  slab.acceptGhosts(SlabSide::kHigher, fromHigher);
}

void RankTeam::gatherEach(PackedLeaves leaves, int root, const std::function<void(PackedLeaves)>& take) const {
  std::uint64_t size = leaves.size();
  std::vector<std::uint64_t> sizes(static_cast<std::size_t>(mSize));
  MPI_Gather(&size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, root, mCommunicator);
  std::vector<MPI_Request> requests;
  if (mRank != root) {
    postSend(leaves, root, mCommunicator, requests);
    waitAll(requests);
    return;
  }
  for (int r = 0; r < mSize; ++r) {
    if (r == root) {
      take(std::move(leaves));
      continue;
    }
    PackedLeaves piece(sizes[static_cast<std::size_t>(r)]);
    postReceive(piece, r, mCommunicator, requests);
    waitAll(requests);
    take(std::move(piece));
  }
}

std::vector<PackedLeaves> RankTeam::exchange(std::vector<PackedLeaves> toEach) const {
  const std::size_t ranks = static_cast<std::size_t>(mSize);
  if (toEach.size() != ranks)
    throw std::invalid_argument("RankTeam::exchange: " + std::to_string(toEach.size()) + " parcels for " +
                                std::to_string(mSize) + " ranks (one each, this rank's included)");
  std::vector<std::uint64_t> sizesTo(ranks), sizesFrom(ranks);
  for (std::size_t r = 0; r < ranks; ++r) sizesTo[r] = toEach[r].size();
  MPI_Alltoall(sizesTo.data(), 1, MPI_UINT64_T, sizesFrom.data(), 1, MPI_UINT64_T, mCommunicator);
  std::vector<PackedLeaves> fromEach(ranks);
  std::vector<MPI_Request> requests;
  for (std::size_t r = 0; r < ranks; ++r) {
    if (static_cast<int>(r) == mRank) continue;
    fromEach[r].resize(sizesFrom[r]);
    postReceive(fromEach[r], static_cast<int>(r), mCommunicator, requests);
    postSend(toEach[r], static_cast<int>(r), mCommunicator, requests);
  }
  waitAll(requests);
  fromEach[static_cast<std::size_t>(mRank)] = std::move(toEach[static_cast<std::size_t>(mRank)]);
  return fromEach;
}

}  // namespace levelfuse::mpi
