// levelfuse: scans handed to the loader's taker as they are read, or
// collected (private to the readers).
#pragma once

#include <levelfuse/core/Parallel.h>
#include <levelfuse/io/LoadProgress.h>
#include <levelfuse/io/Scans.h>

#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <exception>
#include <optional>
#include <utility>
#include <vector>

namespace levelfuse::io {

class ScanDelivery {
 public:
  explicit ScanDelivery(const ScanLoadOptions& options) : mTake(options.take) {}
  /// Hands `map` over, or keeps it.
  void deliver(RangeMap&& map) {
    ++mDelivered;
    if (mTake) mTake(std::move(map));
    else mMaps.push_back(std::move(map));
  }
  std::size_t delivered() const { return mDelivered; }
  /// The scans kept (none when they were handed over).
  std::vector<RangeMap> kept() { return std::move(mMaps); }

 private:
  const ScanTaker& mTake;
  std::vector<RangeMap> mMaps;
  std::size_t mDelivered = 0;
};

/// Reads `count` frames, `read(i)` making the i-th, a batch at a time in
/// parallel (twice as many frames as there are threads), and hands them over
/// in order from the calling thread, telling the progress after each and
/// asking the interrupter before each. While the calling thread hands a batch
/// over, the other threads read the next: no more than two batches are in
/// flight. Of the frames that cannot be read, the first in order throws: the
/// same error whatever the number of threads.
template <typename Read>
void deliverFrames(std::size_t count, const Read& read, ScanDelivery& scans, const ScanLoadOptions& options) {
  struct Batch {
    std::vector<std::optional<RangeMap>> frames;
    std::vector<std::exception_ptr> failures;
  };
  const std::size_t size = itemsInFlight();
  std::array<Batch, 2> batches;
  for (Batch& b : batches) {
    b.frames.resize(size);
    b.failures.resize(size);
  }
  const auto readBatch = [&](Batch& b, std::size_t first) {
    parallelFor(std::min(size, count - first), 1, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) try {
          b.frames[k].emplace(read(first + k));
        } catch (...) {
          b.failures[k] = std::current_exception();
        }
    });
  };
  const auto handOver = [&](Batch& b, std::size_t first) {
    for (std::size_t k = 0; k < std::min(size, count - first); ++k) {
      checkInterrupter(options.interrupter);
      if (b.failures[k]) std::rethrow_exception(b.failures[k]);
      scans.deliver(std::move(*b.frames[k]));
      b.frames[k].reset();
      reportLoaded(options.progress, scans.delivered(), count);
    }
  };
  checkInterrupter(options.interrupter);
  if (count > 0) readBatch(batches[0], 0);
  for (std::size_t first = 0, current = 0; first < count; first += size, current ^= 1) {
    tbb::task_group next;
    if (first + size < count) next.run([&, first, current] { readBatch(batches[current ^ 1], first + size); });
    try {
      handOver(batches[current], first);
    } catch (...) {
      next.cancel();
      next.wait();
      throw;
    }
    next.wait();
  }
}

}  // namespace levelfuse::io
