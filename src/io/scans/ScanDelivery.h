// levelfuse: scans handed to the loader's taker as they are read, or
// collected (private to the readers).
#pragma once

#include <levelfuse/core/MadeAhead.h>
#include <levelfuse/io/scans/LoadProgress.h>
#include <levelfuse/io/scans/ScanLoadOptions.h>

#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace levelfuse::io {

class ScanDelivery {
 public:
  explicit ScanDelivery(const ScanLoadOptions& options) : mTake(options.take), mWanted(options.wanted) {}
  /// Hands `map`, the next scan, over or keeps it, if it is wanted (ScanLoadOptions::wanted).
  void offer(RangeMap&& map) {
    if (!mWanted || mWanted(mOffered++)) deliver(std::move(map));
  }
  /// Offers `map`, the next scan of a file that does not say how many it
  /// holds, and tells `progress` (k, k) after the k-th delivered.
  void offerAsRead(RangeMap&& map, const LoadProgress& progress) {
    offer(std::move(map));
    reportLoaded(progress, mDelivered, mDelivered);
  }
  /// Hands `map` over, or keeps it: a scan already found wanted.
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
  const std::function<bool(std::size_t)>& mWanted;
  std::vector<RangeMap> mMaps;
  std::size_t mDelivered = 0, mOffered = 0;
};

/// Reads the wanted ones (ScanLoadOptions::wanted, asked of every frame
/// first) of `count` frames, `read(i)` making the i-th, in parallel a batch
/// ahead of the calling thread, which hands them over in order, telling the
/// progress after each and asking the interrupter before each (takeMadeAhead:
/// of the frames that cannot be read, the first in order throws).
template <typename Read>
void deliverFrames(std::size_t count, const Read& read, ScanDelivery& scans, const ScanLoadOptions& options) {
  std::vector<std::size_t> wanted;
  for (std::size_t i = 0; i < count; ++i)
    if (!options.wanted || options.wanted(i)) wanted.push_back(i);
  takeMadeAhead<RangeMap>(
      wanted.size(), [&](std::size_t k) { return read(wanted[k]); },
      [&](std::size_t, RangeMap&& frame) {
        scans.deliver(std::move(frame));
        reportLoaded(options.progress, scans.delivered(), wanted.size());
      },
      options.interrupter);
}

/// Reads every ScanLoadOptions::frameStride-th of `frameCount` frames as
/// deliverFrames does, `read(f)` making frame f; returns the frames kept.
template <typename Read>
std::vector<RangeMap> deliverStridedFrames(std::size_t frameCount, const Read& read, const ScanLoadOptions& options) {
  ScanDelivery scans(options);
  const std::size_t stride = static_cast<std::size_t>(options.frameStride);
  const std::size_t total = (frameCount + stride - 1) / stride;
  deliverFrames(total, [&](std::size_t i) { return read(i * stride); }, scans, options);
  return scans.kept();
}

}  // namespace levelfuse::io
