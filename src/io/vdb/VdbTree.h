// levelfuse: a .vdb grid's tree in the standard configuration (a root over
// internal nodes of 32^3 and 16^3 children over leaves of 8^3 values),
// checked as OpenVDB 10 reads it (Tree::readTopology, then readBuffers).
#pragma once

#include "VdbCompressedValues.h"

#include <cstdint>
#include <vector>

namespace levelfuse::io::detail {

/// A tree's nodes, as the topology declares them.
struct VdbTreeTopology {
  std::uint64_t rootTiles = 0, upperNodes = 0, lowerNodes = 0;
  /// The active values of each leaf, in the order of the leaves' buffers.
  std::vector<std::uint16_t> leafActiveCounts;

  /// Bytes the tree takes in memory (OpenVDB's nodes for values of
  /// `valueBytes` bytes), roughly.
  double memoryBytes(std::uint32_t valueBytes) const;
};

/// Checks and skips a tree's topology: root tiles and children (aligned, in
/// order, each once), internal nodes' masks (no slot both a child and a
/// value) and their values, leaves' value masks.
VdbTreeTopology skipVdbTopology(VdbByteReader& reader, const VdbValueLayout& layout);

/// Checks and skips the leaves' buffers that follow a topology.
void skipVdbLeafBuffers(VdbByteReader& reader, const VdbValueLayout& layout, const VdbTreeTopology& topology);

}  // namespace levelfuse::io::detail
