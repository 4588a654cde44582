// levelfuse: a .vdb grid's tree, checked.

#include "VdbTree.h"

#include <algorithm>
#include <array>
#include <bitset>
#include <memory>
#include <string>

namespace levelfuse::io::detail {
namespace {

/// log2 of the children per axis of each level: leaf 8^3, lower 16^3, upper 32^3.
constexpr int kLeafLog2 = 3, kLowerLog2 = 4, kUpperLog2 = 5;
/// Voxels per axis an upper node spans: its origin's alignment in the root.
constexpr std::int32_t kUpperSpan = 1 << (kLeafLog2 + kLowerLog2 + kUpperLog2);
constexpr std::uint32_t kLeafValues = 1u << (3 * kLeafLog2);

/// The bytes a root child takes at least in a file: its coordinates, two
/// masks and the kind byte of its values.
constexpr std::uint64_t kMinUpperNodeBytes = 12 + 2 * (1u << (3 * kUpperLog2)) / 8 + 1;

/// A node's child and value masks (openvdb::util::NodeMask::load).
template <int Log2>
struct NodeMasks {
  static constexpr std::uint32_t kSize = 1u << (3 * Log2);
  std::bitset<kSize> children, values;

  void read(VdbByteReader& reader) {
    std::array<std::uint64_t, kSize / 64> words{};
    reader.read(words.data(), kSize / 8, "a node's child mask");
    children = toBits(words);
    reader.read(words.data(), kSize / 8, "a node's value mask");
    values = toBits(words);
    if ((children & values).any()) reader.fail("a node's slot is both a child and a value");
  }

  static std::bitset<kSize> toBits(const std::array<std::uint64_t, kSize / 64>& words) {
    std::bitset<kSize> bits;
    for (std::uint32_t i = 0; i < kSize; ++i)
      if (words[i / 64] >> (i % 64) & 1) bits.set(i);
    return bits;
  }
};

void skipLeafTopology(VdbByteReader& reader, VdbTreeTopology& topology) {
  std::array<std::uint64_t, kLeafValues / 64> mask{};
  reader.read(mask.data(), sizeof(mask), "a leaf node's value mask");
  std::uint32_t active = 0;
  for (const std::uint64_t word : mask) active += static_cast<std::uint32_t>(__builtin_popcountll(word));
  topology.leafActiveCounts.push_back(static_cast<std::uint16_t>(active));
}

void skipLowerTopology(VdbByteReader& reader, const VdbValueLayout& layout, VdbTreeTopology& topology) {
  NodeMasks<kLowerLog2> masks;
  masks.read(reader);
  skipCompressedValues(reader, layout, masks.kSize, static_cast<std::uint32_t>(masks.values.count()),
                       /*decompress=*/true);
  ++topology.lowerNodes;
  for (std::uint32_t i = 0; i < masks.kSize; ++i)
    if (masks.children[i]) skipLeafTopology(reader, topology);
}

void skipUpperTopology(VdbByteReader& reader, const VdbValueLayout& layout, VdbTreeTopology& topology) {
  auto masks = std::make_unique<NodeMasks<kUpperLog2>>();
  masks->read(reader);
  skipCompressedValues(reader, layout, masks->kSize, static_cast<std::uint32_t>(masks->values.count()),
                       /*decompress=*/true);
  ++topology.upperNodes;
  for (std::uint32_t i = 0; i < masks->kSize; ++i)
    if (masks->children[i]) skipLowerTopology(reader, layout, topology);
}

using Origin = std::array<std::int32_t, 3>;

/// A root entry's coordinates: aligned to the upper nodes' span, after the
/// entry before it (OpenVDB writes its table in order; the buffers follow
/// that order too, and a repeated key would lose a node).
Origin readRootKey(VdbByteReader& reader, const Origin* previous, const char* what) {
  Origin origin{};
  reader.read(origin.data(), sizeof(origin), what);
  for (const std::int32_t c : origin)
    if (c % kUpperSpan != 0)
      reader.fail(std::string(what) + " (" + std::to_string(origin[0]) + ", " + std::to_string(origin[1]) + ", " +
                  std::to_string(origin[2]) + ") is not a multiple of " + std::to_string(kUpperSpan));
  if (previous && !(*previous < origin)) reader.fail(std::string(what) + " out of order or repeated");
  return origin;
}

}  // namespace

double VdbTreeTopology::memoryBytes(std::uint32_t valueBytes) const {
  // A node's table holds a child pointer or a value per slot (openvdb::tree::NodeUnion).
  const double slotBytes = std::max<std::uint32_t>(8, (valueBytes + 7) / 8 * 8);
  const double leaf = kLeafValues * double(valueBytes) + 96;
  const double lower = (1u << (3 * kLowerLog2)) * slotBytes + 2 * 512 + 32;
  const double upper = (1u << (3 * kUpperLog2)) * slotBytes + 2 * 4096 + 32;
  const double rootEntry = 64 + slotBytes;
  return double(leafActiveCounts.size()) * leaf + double(lowerNodes) * lower + double(upperNodes) * upper +
         double(rootTiles + upperNodes) * rootEntry;
}

VdbTreeTopology skipVdbTopology(VdbByteReader& reader, const VdbValueLayout& layout) {
  VdbTreeTopology topology;
  const auto buffers = reader.read<std::int32_t>("the tree's buffer count");
  if (buffers != 1) reader.fail("the tree declares " + std::to_string(buffers) + " buffers; OpenVDB writes 1");
  reader.skip(layout.valueBytes, "the background value");
  const auto tiles = reader.read<std::uint32_t>("the root's tile count");
  const auto children = reader.read<std::uint32_t>("the root's child count");
  const std::uint64_t tileBytes = 12 + std::uint64_t(layout.valueBytes) + 1;
  if (tiles > reader.remaining() / tileBytes || children > reader.remaining() / kMinUpperNodeBytes ||
      tiles * tileBytes + children * kMinUpperNodeBytes > reader.remaining())
    reader.fail("the root declares " + std::to_string(tiles) + " tiles and " + std::to_string(children) +
                " children, more than the " + std::to_string(reader.remaining()) + " bytes left can hold");

  std::vector<Origin> tileKeys;
  for (std::uint32_t i = 0; i < tiles; ++i) {
    tileKeys.push_back(readRootKey(reader, tileKeys.empty() ? nullptr : &tileKeys.back(), "a root tile"));
    reader.skip(layout.valueBytes, "a root tile's value");
    const auto active = reader.read<std::uint8_t>("a root tile's state");
    if (active > 1) reader.fail("a root tile's state " + std::to_string(active) + " is neither 0 nor 1");
  }
  topology.rootTiles = tiles;
  Origin previous{};
  for (std::uint32_t i = 0; i < children; ++i) {
    const Origin origin = readRootKey(reader, i == 0 ? nullptr : &previous, "a root child");
    if (std::binary_search(tileKeys.begin(), tileKeys.end(), origin))
      reader.fail("a root child where the root has a tile");
    previous = origin;
    skipUpperTopology(reader, layout, topology);
  }
  return topology;
}

void skipVdbLeafBuffers(VdbByteReader& reader, const VdbValueLayout& layout, const VdbTreeTopology& topology) {
  for (const std::uint16_t active : topology.leafActiveCounts) {
    reader.skip(kLeafValues / 8, "a leaf node's value mask");
    skipCompressedValues(reader, layout, kLeafValues, active, /*decompress=*/false);
  }
}

}  // namespace levelfuse::io::detail
