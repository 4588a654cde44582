// A team of slabs run as threads of one process.

#include "support/ThreadTeam.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace levelfuse::test {

namespace {

/// The parcels in flight between the ranks, and the barrier around them.
class Board {
 public:
  explicit Board(int size) : mSize(size), mMail(static_cast<std::size_t>(size) * static_cast<std::size_t>(size)) {}

  /// Every rank's `toEach[r]` to rank r; what each sent to `rank`, in rank order.
  std::vector<PackedLeaves> allToAll(int rank, std::vector<PackedLeaves> toEach) {
    if (toEach.size() != static_cast<std::size_t>(mSize)) throw std::invalid_argument("ThreadTeam: one parcel per rank");
    for (int to = 0; to < mSize; ++to) mail(rank, to) = std::move(toEach[static_cast<std::size_t>(to)]);
    arriveAndWait();
    std::vector<PackedLeaves> fromEach(static_cast<std::size_t>(mSize));
    for (int from = 0; from < mSize; ++from) fromEach[static_cast<std::size_t>(from)] = std::move(mail(from, rank));
    arriveAndWait();  // nobody posts the next parcels before every rank has taken these
    return fromEach;
  }

  /// Stops every rank at its next barrier.
  void breakDown() {
    std::lock_guard<std::mutex> lock(mMutex);
    mBroken = true;
    mWoken.notify_all();
  }

  int size() const { return mSize; }

 private:
  PackedLeaves& mail(int from, int to) {
    return mMail[static_cast<std::size_t>(from) * static_cast<std::size_t>(mSize) + static_cast<std::size_t>(to)];
  }

  void arriveAndWait() {
    std::unique_lock<std::mutex> lock(mMutex);
    const std::uint64_t generation = mGeneration;
    if (++mArrived == mSize) {
      mArrived = 0;
      ++mGeneration;
      mWoken.notify_all();
    } else {
      mWoken.wait(lock, [&] { return mGeneration != generation || mBroken; });
    }
    if (mBroken) throw std::runtime_error("ThreadTeam: another rank failed");
  }

  const int mSize;
  std::vector<PackedLeaves> mMail;  ///< [from * size + to]
  std::mutex mMutex;
  std::condition_variable mWoken;
  int mArrived = 0;
  std::uint64_t mGeneration = 0;
  bool mBroken = false;
};

template <typename T>
PackedLeaves bytesOf(const T& value) {
  PackedLeaves out(sizeof(T));
  std::memcpy(out.data(), &value, sizeof(T));
  return out;
}

template <typename T>
T valueOf(const PackedLeaves& bytes) {
  T value;
  std::memcpy(&value, bytes.data(), sizeof(T));
  return value;
}

class ThreadTeam : public SlabTeam {
 public:
  ThreadTeam(Board& board, int rank) : mBoard(board), mRank(rank) {}

  int rank() const override { return mRank; }
  int size() const override { return mBoard.size(); }

  double largest(double value) const override {
    double out = value;
    for (const PackedLeaves& v : everyones(bytesOf(value))) out = std::max(out, valueOf<double>(v));
    return out;
  }
  std::uint64_t total(std::uint64_t count) const override {
    std::uint64_t out = 0;
    for (const PackedLeaves& v : everyones(bytesOf(count))) out += valueOf<std::uint64_t>(v);
    return out;
  }
  StepTally sum(const StepTally& tally) const override {
    StepTally out;
    for (const PackedLeaves& v : everyones(bytesOf(tally))) out += valueOf<StepTally>(v);
    return out;
  }
  void refreshGhosts(SlabField& slab) const override {
    std::vector<PackedLeaves> toEach(static_cast<std::size_t>(size()));
    if (mRank > 0) toEach[static_cast<std::size_t>(mRank - 1)] = slab.ghostsFor(SlabSide::kLower);
    if (mRank + 1 < size()) toEach[static_cast<std::size_t>(mRank + 1)] = slab.ghostsFor(SlabSide::kHigher);
    std::vector<PackedLeaves> fromEach = mBoard.allToAll(mRank, std::move(toEach));
    if (mRank > 0) slab.acceptGhosts(SlabSide::kLower, fromEach[static_cast<std::size_t>(mRank - 1)]);
    if (mRank + 1 < size()) slab.acceptGhosts(SlabSide::kHigher, fromEach[static_cast<std::size_t>(mRank + 1)]);
  }
  void gatherEach(PackedLeaves leaves, int root, const std::function<void(PackedLeaves)>& take) const override {
    std::vector<PackedLeaves> toEach(static_cast<std::size_t>(size()));
    toEach[static_cast<std::size_t>(root)] = std::move(leaves);
    std::vector<PackedLeaves> fromEach = mBoard.allToAll(mRank, std::move(toEach));
    if (mRank != root) return;
    for (PackedLeaves& piece : fromEach) take(std::move(piece));
  }
  std::vector<PackedLeaves> exchange(std::vector<PackedLeaves> toEach) const override {
    return mBoard.allToAll(mRank, std::move(toEach));
  }

 private:
  std::vector<PackedLeaves> everyones(const PackedLeaves& mine) const {
    return mBoard.allToAll(mRank, std::vector<PackedLeaves>(static_cast<std::size_t>(size()), mine));
  }

  Board& mBoard;
  const int mRank;
};

}  // namespace

void runOnThreadTeam(int size, const std::function<void(const SlabTeam&)>& body) {
  Board board(size);
  std::mutex failed;
  std::exception_ptr first;  // the cause: the others fail after it, at a barrier
  std::vector<std::thread> ranks;
  for (int r = 0; r < size; ++r)
    ranks.emplace_back([&, r] {
      try {
        // Each rank's parallel work stays on its own arena, as a process's
        // would: no rank runs another's tasks.
        tbb::task_arena own;
        own.execute([&] {
          const ThreadTeam team(board, r);
          body(team);
        });
      } catch (...) {
        {
          std::lock_guard<std::mutex> lock(failed);
          if (!first) first = std::current_exception();
        }
        board.breakDown();
      }
    });
  for (std::thread& t : ranks) t.join();
  if (first) std::rethrow_exception(first);
}

}  // namespace levelfuse::test
