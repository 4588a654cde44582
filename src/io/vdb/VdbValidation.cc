// levelfuse: a .vdb file checked before OpenVDB reads it.

#include "VdbValidation.h"

#include "VdbByteReader.h"
#include "VdbCompressedValues.h"
#include "VdbRecords.h"
#include "VdbTree.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/MemoryBudget.h>

#include <openvdb/io/Compression.h>
#include <openvdb/version.h>

#include <cctype>
#include <cstdint>
#include <vector>
#include <string>

namespace levelfuse::io::detail {
namespace {

constexpr std::int64_t kMagic = 0x56444220;  // OPENVDB_MAGIC
/// Per-grid compression and mask compression (OpenVDB 3) up to OpenVDB 10's format.
constexpr std::uint32_t kOldestVersion = openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION;
constexpr std::uint32_t kNewestVersion = openvdb::OPENVDB_FILE_VERSION;
constexpr std::uint32_t kKnownCompression =
    openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK | openvdb::io::COMPRESS_BLOSC;
/// A grid descriptor's bytes at least: three string lengths, three offsets.
constexpr std::uint64_t kMinGridDescriptorBytes = 3 * 4 + 3 * 8;
constexpr std::size_t kUuidLength = 36;
/// What a grid descriptor's type ends in when its values are stored as half floats.
const char* const kHalfFloatSuffix = "_HalfFloat";

const char* const kGridTooLargeAdvice = "use a coarser grid or a machine with more memory";

/// The grid types levelfuse reads: the standard tree configuration with
/// values that OpenVDB stores in its generic leaf nodes.
struct GridValueType {
  const char* treeType;
  std::uint32_t valueBytes;
  std::uint32_t halfBytes;  ///< as half floats; valueBytes for types OpenVDB never stores as half
};
const GridValueType kGridValueTypes[] = {
    {"Tree_float_5_4_3", 4, 2},   {"Tree_double_5_4_3", 8, 2}, {"Tree_int32_5_4_3", 4, 4},
    {"Tree_int64_5_4_3", 8, 8},   {"Tree_vec3s_5_4_3", 12, 6}, {"Tree_vec3d_5_4_3", 24, 6},
    {"Tree_vec3i_5_4_3", 12, 12}};
const char* const kSupportedGridTypes =
    "levelfuse reads grids of float, double, int32, int64, vec3s, vec3d and vec3i values in the standard tree "
    "configuration (5, 4, 3)";

const GridValueType* findGridValueType(const std::string& treeType) {
  for (const GridValueType& type : kGridValueTypes)
    if (treeType == type.treeType) return &type;
  return nullptr;
}

bool isUuid(const std::string& text) {
  if (text.size() != kUuidLength) return false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
    if (dash ? text[i] != '-' : !std::isxdigit(static_cast<unsigned char>(text[i]))) return false;
  }
  return true;
}

/// openvdb::io::Archive::readHeader; returns whether grid offsets are stored.
bool skipHeader(VdbByteReader& reader) {
  reader.setContext("the header");
  if (reader.read<std::int64_t>("the magic number") != kMagic)
    reader.fail("the file does not start with OpenVDB's magic number");
  const auto version = reader.read<std::uint32_t>("the file format version");
  if (version < kOldestVersion || version > kNewestVersion)
    reader.fail("file format version " + std::to_string(version) + "; levelfuse reads versions " +
                std::to_string(kOldestVersion) + " to " + std::to_string(kNewestVersion) + " (OpenVDB 3 to " +
                std::to_string(OPENVDB_LIBRARY_MAJOR_VERSION_NUMBER) + ")");
  reader.skip(8, "the library version");
  const auto hasGridOffsets = reader.read<std::uint8_t>("the grid offsets flag");
  if (hasGridOffsets > 1) reader.fail("the grid offsets flag is " + std::to_string(hasGridOffsets) + ", not 0 or 1");
  std::string uuid(kUuidLength, '\0');
  reader.read(uuid.data(), kUuidLength, "the UUID");
  if (!isUuid(uuid)) reader.fail("the UUID " + quote(uuid) + " is not one");
  return hasGridOffsets == 1;
}

struct GridDescriptor {
  std::string name, treeType, parent;
  std::int64_t gridPos = 0, blockPos = 0, endPos = 0;
  const GridValueType* valueType = nullptr;
};

/// openvdb::io::GridDescriptor::read, checked against the grids before it.
GridDescriptor readGridDescriptor(VdbByteReader& reader, const std::vector<GridDescriptor>& before) {
  GridDescriptor grid;
  grid.name = readVdbString(reader, "a grid's name");
  grid.treeType = readVdbString(reader, "a grid's type");
  grid.parent = readVdbString(reader, "a grid's instance parent");
  grid.gridPos = reader.read<std::int64_t>("a grid's offset");
  grid.blockPos = reader.read<std::int64_t>("a grid's offset");
  grid.endPos = reader.read<std::int64_t>("a grid's offset");

  const std::string suffix = kHalfFloatSuffix;
  std::string treeType = grid.treeType;
  // Whether values are half floats is the grid's metadata's to say (skipVdbMetadata).
  if (treeType.size() >= suffix.size() && treeType.compare(treeType.size() - suffix.size(), suffix.size(), suffix) == 0)
    treeType.resize(treeType.size() - suffix.size());
  grid.valueType = findGridValueType(treeType);
  if (!grid.valueType)
    reader.fail("grid " + quote(grid.name) + " is of type " + quote(grid.treeType) + "; " + kSupportedGridTypes);
  for (const GridDescriptor& other : before)
    if (other.name == grid.name) reader.fail("two grids are named " + quote(grid.name));
  if (!grid.parent.empty()) {
    const GridDescriptor* parent = nullptr;
    for (const GridDescriptor& other : before)
      if (other.name == grid.parent) parent = &other;
    if (!parent || !parent->parent.empty() || parent->treeType != grid.treeType)
      reader.fail("grid " + quote(grid.name) + " shares the tree of " + quote(grid.parent) +
                  ", which is no grid of the same type before it");
  }
  return grid;
}

/// One grid (openvdb::io::Archive::readGrid); returns the memory its tree needs.
double skipGrid(VdbByteReader& reader, const GridDescriptor& grid, bool hasGridOffsets) {
  if (hasGridOffsets) {
    // An instance has no buffers of its own, and OpenVDB leaves its block offset 0.
    const std::int64_t start = static_cast<std::int64_t>(reader.position());
    const std::int64_t blockPos = grid.parent.empty() ? grid.blockPos : grid.gridPos;
    if (grid.endPos > 0 && static_cast<std::uint64_t>(grid.endPos) > reader.size())
      reader.fail("the grid ends at byte " + std::to_string(grid.endPos) + ", beyond the file's " +
                  std::to_string(reader.size()) + " bytes (truncated?)");
    if (grid.gridPos < start || blockPos < grid.gridPos || grid.endPos < blockPos)
      reader.fail("the grid's offsets (" + std::to_string(grid.gridPos) + ", " + std::to_string(grid.blockPos) +
                  ", " + std::to_string(grid.endPos) + ") are not in order after its descriptor");
    reader.seek(static_cast<std::uint64_t>(grid.gridPos), "the grid's offset");
  }
  VdbValueLayout layout;
  layout.compression = reader.read<std::uint32_t>("the grid's compression flags");
  if (layout.compression & ~kKnownCompression)
    reader.fail("unknown compression flags " + std::to_string(layout.compression));
  const bool halfFloat = skipVdbMetadata(reader, "the grid's metadata");
  layout.valueBytes = grid.valueType->valueBytes;
  layout.halfFloat = halfFloat && grid.valueType->halfBytes != grid.valueType->valueBytes;
  layout.storedBytes = layout.halfFloat ? grid.valueType->halfBytes : grid.valueType->valueBytes;

  skipVdbTransform(reader);
  double memory = 0;
  if (grid.parent.empty()) {
    const VdbTreeTopology topology = skipVdbTopology(reader, layout);
    if (hasGridOffsets && reader.position() != static_cast<std::uint64_t>(grid.blockPos))
      reader.fail("the topology ends at byte " + std::to_string(reader.position()) +
                  ", but the grid's descriptor says its buffers start at " + std::to_string(grid.blockPos));
    skipVdbLeafBuffers(reader, layout, topology);
    memory = topology.memoryBytes(layout.valueBytes);
  }
  if (hasGridOffsets && reader.position() != static_cast<std::uint64_t>(grid.endPos))
    reader.fail("the grid ends at byte " + std::to_string(reader.position()) + ", but its descriptor says " +
                std::to_string(grid.endPos));
  return memory;
}

}  // namespace

void validateVdbFile(const std::string& path, const MemoryBudget& budget) {
  VdbByteReader reader(path);
  const bool hasGridOffsets = skipHeader(reader);
  reader.setContext("the file's metadata");
  skipVdbMetadata(reader, "the file's metadata");
  reader.setContext("the grid count");
  const auto count = reader.read<std::int32_t>("the grid count");
  if (count < 0 || static_cast<std::uint64_t>(count) > reader.remaining() / kMinGridDescriptorBytes)
    reader.fail("the file declares " + std::to_string(count) + " grids; the " + std::to_string(reader.remaining()) +
                " bytes left cannot hold them");
  std::vector<GridDescriptor> grids;
  double memory = 0;
  for (std::int32_t i = 0; i < count; ++i) {
    const std::string ordinal = std::to_string(i + 1) + " of " + std::to_string(count);
    reader.setContext("grid descriptor " + ordinal);
    grids.push_back(readGridDescriptor(reader, grids));
    reader.setContext("grid " + quote(grids.back().name) + " (" + ordinal + ")");
    memory += skipGrid(reader, grids.back(), hasGridOffsets);
  }
  requireMemory(budget, path, memory, "the grids in the file", kGridTooLargeAdvice);
}

}  // namespace levelfuse::io::detail
