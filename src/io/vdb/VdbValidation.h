// levelfuse: a .vdb file checked before OpenVDB reads it.
#pragma once

#include <levelfuse/core/MemoryBudget.h>

#include <string>

namespace levelfuse::io::detail {

/// Walks the .vdb file at `path` as OpenVDB 10 reads it (header, file
/// metadata, grid descriptors and their offsets, each grid's metadata,
/// transform, topology and leaf buffers) and checks every declared count and
/// size against the bytes left and against what its node holds, before
/// OpenVDB allocates anything from them; then the memory the grids need
/// against `budget`. Throws InputError, naming the file and what is
/// wrong, at the first problem. Reads file format versions 222 to 224
/// (OpenVDB 3 and later) and trees of the standard configuration.
void validateVdbFile(const std::string& path, const MemoryBudget& budget);

}  // namespace levelfuse::io::detail
