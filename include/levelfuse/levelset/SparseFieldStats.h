// levelfuse: the counts and bytes of a sparse field (SparseField::stats).
#pragma once

#include <cstddef>

namespace levelfuse {

/// Counts and bytes of a sparse field.
struct SparseFieldStats {
  std::size_t activeSetVoxels = 0;    ///< |L0|
  std::size_t bandVoxels = 0;      ///< voxels in all layers, L0 included
  std::size_t leafNodes = 0;
  std::size_t memoryBytes = 0;     ///< values, layers and the engine's bookkeeping
};

}  // namespace levelfuse
