// levelfuse: strings, metadata and transforms of a .vdb file, checked.

#include "VdbRecords.h"

#include "VdbCompressedValues.h"

#include <levelfuse/io/InputError.h>

#include <openvdb/Grid.h>
#include <openvdb/Metadata.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/points/StreamCompression.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace levelfuse::io::detail {
namespace {

/// The longest name (of a grid, a type, a metadata item) levelfuse reads.
constexpr std::uint32_t kMaxNameBytes = 1 << 16;

/// Bytes of a metadata item at least: its name, type and size fields.
constexpr std::uint64_t kMinMetadataItemBytes = 12;

/// The bytes a leaf node takes in a file at least (its value mask, twice):
/// delayed-load metadata declares a number per leaf.
constexpr std::uint64_t kMinLeafBytes = 128;

/// One array of openvdb::io::DelayedLoadMetadata: raw, or blosc-compressed
/// with a header that agrees with the array's (padded) size.
void skipDelayedLoadArray(VdbByteReader& reader, std::uint32_t count, std::uint32_t itemBytes,
                          std::uint32_t compressedBytes) {
  const std::uint64_t bytes = std::uint64_t(count) * itemBytes;
  if (compressedBytes == 0) {
    reader.skip(bytes, "delayed-load metadata");
    return;
  }
  // OpenVDB pads arrays shorter than BLOSC_PAD_BYTES to it before compressing them.
  const std::uint64_t padded = std::max<std::uint64_t>(bytes, openvdb::compression::BLOSC_PAD_BYTES);
  skipBloscBlock(reader, padded, compressedBytes, "delayed-load metadata");
}

/// openvdb::io::DelayedLoadMetadata::readValue: a count, a mask array and an
/// array of compressed sizes, within the item's `numBytes`.
void skipDelayedLoadMetadata(VdbByteReader& reader, std::uint32_t numBytes) {
  if (numBytes == 0) return;
  const std::uint64_t start = reader.position();
  reader.require(numBytes, "delayed-load metadata");
  const auto count = reader.read<std::uint32_t>("delayed-load metadata");
  if (count > reader.size() / kMinLeafBytes)
    reader.fail("delayed-load metadata declares " + std::to_string(count) + " leaf nodes, more than the file holds");
  skipDelayedLoadArray(reader, count, sizeof(openvdb::io::DelayedLoadMetadata::MaskType),
                       reader.read<std::uint32_t>("delayed-load metadata"));
  const auto sizesBytes = reader.read<std::uint32_t>("delayed-load metadata");
  if (sizesBytes != UINT32_MAX)
    skipDelayedLoadArray(reader, count, sizeof(openvdb::io::DelayedLoadMetadata::CompressedSizeType), sizesBytes);
  const std::uint64_t used = reader.position() - start;
  if (used > numBytes)
    reader.fail("delayed-load metadata takes " + std::to_string(used) + " bytes, more than its declared " +
                std::to_string(numBytes));
  reader.skip(numBytes - used, "delayed-load metadata");
}

/// The size every item of a registered fixed-size metadata type has.
std::uint32_t fixedMetadataBytes(const std::string& type) {
  return openvdb::Metadata::createMetadata(type)->size();
}

/// OpenVDB's linear maps and the bytes each stores (math/Maps.h: the
/// matrix, or the scale and translation with their derived vectors).
std::uint32_t linearMapBytes(const std::string& type) {
  static const std::pair<const char*, std::uint32_t> kMaps[] = {
      {"AffineMap", 16 * 8},         {"UnitaryMap", 16 * 8},         {"ScaleMap", 5 * 24},
      {"UniformScaleMap", 5 * 24},   {"TranslationMap", 24},         {"ScaleTranslateMap", 6 * 24},
      {"UniformScaleTranslateMap", 6 * 24}};
  for (const auto& [name, bytes] : kMaps)
    if (type == name) return bytes;
  return 0;
}

}  // namespace

std::string readVdbString(VdbByteReader& reader, const char* what) {
  const auto length = reader.read<std::uint32_t>(what);
  if (length > kMaxNameBytes)
    reader.fail(std::string(what) + " declares " + std::to_string(length) + " bytes; levelfuse reads at most " +
                std::to_string(kMaxNameBytes));
  std::string text(length, '\0');
  reader.read(text.data(), length, what);
  return text;
}

bool skipVdbMetadata(VdbByteReader& reader, const char* what) {
  bool halfFloat = false;
  const auto count = reader.read<std::uint32_t>(what);
  if (count > reader.remaining() / kMinMetadataItemBytes)
    reader.fail(std::string(what) + " declares " + std::to_string(count) + " items, more than the " +
                std::to_string(reader.remaining()) + " bytes left can hold");
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string name = readVdbString(reader, "a metadata name");
    const std::string type = readVdbString(reader, "a metadata type");
    const auto numBytes = reader.read<std::uint32_t>("a metadata size");
    reader.require(numBytes, "a metadata value");
    const auto problem = [&](const std::string& text) {
      reader.fail("metadata " + quote(name) + " of type " + quote(type) + ": " + text);
    };
    const bool isBool = type == openvdb::BoolMetadata::staticTypeName();
    if (name == openvdb::GridBase::META_SAVE_HALF_FLOAT && !isBool) problem("a bool is expected");
    if (!openvdb::Metadata::isRegisteredType(type) || type == openvdb::StringMetadata::staticTypeName()) {
      reader.skip(numBytes, "a metadata value");
    } else if (type == openvdb::io::DelayedLoadMetadata::staticTypeName()) {
      skipDelayedLoadMetadata(reader, numBytes);
    } else {
      const std::uint32_t expected = fixedMetadataBytes(type);
      if (numBytes != expected)
        problem("declares " + std::to_string(numBytes) + " bytes; the type has " + std::to_string(expected));
      if (isBool) {
        const auto value = reader.read<std::uint8_t>("a metadata value");
        if (value > 1) problem("the value " + std::to_string(value) + " is neither 0 nor 1");
        if (name == openvdb::GridBase::META_SAVE_HALF_FLOAT) halfFloat = value == 1;
      } else {
        reader.skip(numBytes, "a metadata value");
      }
    }
  }
  return halfFloat;
}

void skipVdbTransform(VdbByteReader& reader) {
  const std::string type = readVdbString(reader, "the transform's type");
  const std::uint32_t bytes = linearMapBytes(type);
  if (bytes == 0)
    reader.fail("a transform of type " + quote(type) +
                "; levelfuse reads the linear maps (AffineMap, UnitaryMap, ScaleMap, UniformScaleMap, "
                "TranslationMap, ScaleTranslateMap, UniformScaleTranslateMap)");
  for (std::uint32_t i = 0; i < bytes / 8; ++i) {
    const auto value = reader.read<double>("the transform");
    if (!std::isfinite(value)) reader.fail("the transform holds a number that is not finite");
  }
}

}  // namespace levelfuse::io::detail
