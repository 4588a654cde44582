// levelfuse: the values of one node of a .vdb tree, as OpenVDB 10 stores them
// (openvdb::io::readCompressedValues), checked before OpenVDB reads them.
#pragma once

#include "VdbByteReader.h"

#include <cstdint>

namespace levelfuse::io::detail {

/// How a grid stores its values.
struct VdbValueLayout {
  std::uint32_t compression = 0;  ///< openvdb::io::COMPRESS_* flags of the grid
  std::uint32_t valueBytes = 0;   ///< one value in memory, in tiles and as a background
  std::uint32_t storedBytes = 0;  ///< one value in a node's value block (2 per component as half floats)
  bool halfFloat = false;         ///< stored as half floats (an empty block then holds nothing)
};

/// Checks and skips a block of `compressedBytes` that blosc must decompress
/// to `bytes` (openvdb::io::bloscFromStream trusts blosc's header): no larger
/// than blosc makes it, and a header that declares both sizes.
void skipBloscBlock(VdbByteReader& reader, std::uint64_t bytes, std::uint64_t compressedBytes, const char* what);

/// Checks and skips one node's values: the byte that says which inactive
/// values and selection mask follow, those, and the block of `valueCount`
/// values (`activeCount` of them when only active values are stored). With
/// `decompress`, a compressed block is also decompressed as OpenVDB will:
/// for internal nodes, since OpenVDB leaks the node it reads when their
/// values fail to decompress.
void skipCompressedValues(VdbByteReader& reader, const VdbValueLayout& layout, std::uint32_t valueCount,
                          std::uint32_t activeCount, bool decompress);

}  // namespace levelfuse::io::detail
