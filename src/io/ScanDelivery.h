// levelfuse: scans handed to the loader's taker as they are read, or
// collected (private to the readers).
#pragma once

#include <levelfuse/core/Parallel.h>
#include <levelfuse/io/LoadProgress.h>
#include <levelfuse/io/Scans.h>


#include <algorithm>
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

/// Reads `count` frames, `read(i)` making the i-th, a few at a time in
/// parallel (twice as many as there are threads, no more in flight), and
/// hands them over in order from the calling thread, telling the progress
/// after each and asking the interrupter before each. Of the frames that
/// cannot be read, the first in order throws: the same error whatever the
/// number of threads.
template <typename Read>
void deliverFrames(std::size_t count, const Read& read, ScanDelivery& scans, const ScanLoadOptions& options) {
  const std::size_t batch = itemsInFlight();
  std::vector<std::optional<RangeMap>> frames(batch);
  std::vector<std::exception_ptr> failures(batch);
  for (std::size_t first = 0; first < count; first += batch) {
    checkInterrupter(options.interrupter);
    const std::size_t n = std::min(batch, count - first);
    parallelFor(n, 1, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) try {
          frames[k].emplace(read(first + k));
        } catch (...) {
          failures[k] = std::current_exception();
        }
    });
    for (std::size_t k = 0; k < n; ++k) {
      checkInterrupter(options.interrupter);
      if (failures[k]) std::rethrow_exception(failures[k]);
      scans.deliver(std::move(*frames[k]));
      frames[k].reset();
      reportLoaded(options.progress, scans.delivered(), count);
    }
  }
}

}  // namespace levelfuse::io
