// levelfuse: how far a reader has got through a list of scans or frames.
#pragma once

#include <cstddef>
#include <functional>

namespace levelfuse::io {

/// Told after each scan or frame of a list is read: how many are in, of how
/// many. Readers call it from the thread that called them.
using LoadProgress = std::function<void(std::size_t read, std::size_t total)>;

/// Tells `progress`, if set, that `read` of `total` are in.
inline void reportLoaded(const LoadProgress& progress, std::size_t read, std::size_t total) {
  if (progress) progress(read, total);
}

}  // namespace levelfuse::io
