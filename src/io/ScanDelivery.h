// levelfuse: scans handed to the loader's taker as they are read, or
// collected (private to the readers).
#pragma once

#include <levelfuse/io/Scans.h>

#include <cstddef>
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

}  // namespace levelfuse::io
