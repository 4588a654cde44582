// levelfuse: pixel coordinates as indices into a range map's pixels or cells
// (private to the range maps and the culling by their blocks).
#pragma once

#include <algorithm>

namespace levelfuse::detail {

/// Pixel (or cell) coordinate x as an index from 0 to `last`: clamped before
/// it is made an integer, as a footprint near a camera's plane reaches far
/// beyond the map.
inline int clampedIndex(double x, int last) { return static_cast<int>(std::clamp(x, 0.0, static_cast<double>(last))); }

}  // namespace levelfuse::detail
