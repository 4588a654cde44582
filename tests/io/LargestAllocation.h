// The largest single allocation made through operator new while a probe is
// open, to catch readers that allocate from a declared size they never check.
#pragma once

#include <cstddef>

namespace levelfuse::test {

class LargestAllocation {
 public:
  LargestAllocation();   ///< starts measuring (one probe at a time)
  ~LargestAllocation();  ///< stops
  LargestAllocation(const LargestAllocation&) = delete;
  LargestAllocation& operator=(const LargestAllocation&) = delete;

  /// Bytes of the largest operator new since construction.
  std::size_t bytes() const;
};

}  // namespace levelfuse::test
