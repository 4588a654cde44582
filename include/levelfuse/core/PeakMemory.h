// levelfuse: the most memory the process has held.
#pragma once

#include <cstddef>

namespace levelfuse {

/// The process's peak resident memory so far (bytes).
std::size_t peakResidentBytes();

}  // namespace levelfuse
