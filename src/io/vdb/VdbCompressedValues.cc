// levelfuse: the values of one node of a .vdb tree, checked.

#include "VdbCompressedValues.h"

#include <levelfuse/io/InputError.h>

#include <openvdb/io/Compression.h>

#include <cstring>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

namespace levelfuse::io::detail {
namespace {

/// blosc's header: version, compressor version, flags, type size, then the
/// uncompressed size, the block size and the compressed size (uint32 each).
constexpr std::uint64_t kBloscHeaderBytes = 16;

/// zlib's compressBound(): the most a zip block of `bytes` can take.
std::uint64_t zipBound(std::uint64_t bytes) { return bytes + (bytes >> 12) + (bytes >> 14) + (bytes >> 25) + 13; }

std::uint32_t littleEndian32(const unsigned char* bytes) {
  return bytes[0] | bytes[1] << 8 | bytes[2] << 16 | static_cast<std::uint32_t>(bytes[3]) << 24;
}

/// Decompresses the block of `compressedBytes` that ends at the reader's
/// position with OpenVDB's own function, and fails where OpenVDB would throw.
void requireDecompression(VdbByteReader& reader, bool blosc, std::uint64_t bytes, std::uint64_t compressedBytes) {
  const std::uint64_t end = reader.position();
  reader.seek(end - compressedBytes, "a node's compressed values");
  std::string block(sizeof(std::int64_t) + compressedBytes, '\0');
  const auto count = static_cast<std::int64_t>(compressedBytes);
  std::memcpy(block.data(), &count, sizeof(count));
  reader.read(block.data() + sizeof(count), compressedBytes, "a node's compressed values");
  std::istringstream stream(block);
  std::vector<char> values(bytes);
  try {
    if (blosc) {
      openvdb::io::bloscFromStream(stream, values.data(), values.size());
    } else {
      openvdb::io::unzipFromStream(stream, values.data(), values.size());
    }
  } catch (const std::exception& e) {
    reader.fail(std::string("a node's values do not decompress (") + excerpt(e.what()) + ")");
  }
}

/// A block of `bytes` bytes as openvdb::io::bloscFromStream and
/// unzipFromStream read it: an Int64 byte count, negative (or zero) for raw
/// data, which must then be exactly `bytes` long.
void skipCompressedBlock(VdbByteReader& reader, bool blosc, std::uint64_t bytes, bool decompress) {
  const auto declared = reader.read<std::int64_t>("the byte count of a node's values");
  if (declared <= 0) {
    const std::uint64_t raw = 0 - static_cast<std::uint64_t>(declared);
    if (raw != bytes)
      reader.fail("a node's values are stored as " + std::to_string(raw) + " raw bytes; they take " +
                  std::to_string(bytes));
    reader.skip(bytes, "a node's values");
    return;
  }
  const auto compressed = static_cast<std::uint64_t>(declared);
  if (!blosc) {
    if (compressed > zipBound(bytes))
      reader.fail("a node's " + std::to_string(bytes) + " bytes of values are zipped into " +
                  std::to_string(compressed) + " bytes, more than zip ever takes");
    reader.skip(compressed, "a node's zipped values");
  } else {
    skipBloscBlock(reader, bytes, compressed, "a node's values");
  }
  if (decompress) requireDecompression(reader, blosc, bytes, compressed);
}

}  // namespace

void skipBloscBlock(VdbByteReader& reader, std::uint64_t bytes, std::uint64_t compressedBytes, const char* what) {
  if (compressedBytes < kBloscHeaderBytes || compressedBytes > bytes + kBloscHeaderBytes)
    reader.fail(std::string(what) + ": " + std::to_string(bytes) + " bytes compressed (blosc) into " +
                std::to_string(compressedBytes) + ", which blosc never does");
  unsigned char header[kBloscHeaderBytes];
  reader.read(header, sizeof(header), "a blosc header");
  const std::uint32_t nbytes = littleEndian32(header + 4), cbytes = littleEndian32(header + 12);
  if (nbytes != bytes || cbytes != compressedBytes)
    reader.fail(std::string(what) + ": the blosc header declares " + std::to_string(nbytes) +
                " bytes compressed into " + std::to_string(cbytes) + "; expected " + std::to_string(bytes) +
                " in " + std::to_string(compressedBytes));
  reader.skip(compressedBytes - kBloscHeaderBytes, what);
}

void skipCompressedValues(VdbByteReader& reader, const VdbValueLayout& layout, std::uint32_t valueCount,
                          std::uint32_t activeCount, bool decompress) {
  namespace vio = openvdb::io;
  const auto kind = reader.read<std::int8_t>("the kind of a node's values");
  if (kind < vio::NO_MASK_OR_INACTIVE_VALS || kind > vio::NO_MASK_AND_ALL_VALS)
    reader.fail("a node's values are of unknown kind " + std::to_string(kind) + " (expected 0 to 6)");
  if (kind == vio::NO_MASK_AND_ONE_INACTIVE_VAL || kind == vio::MASK_AND_ONE_INACTIVE_VAL ||
      kind == vio::MASK_AND_TWO_INACTIVE_VALS)
    reader.skip(layout.valueBytes * (kind == vio::MASK_AND_TWO_INACTIVE_VALS ? 2u : 1u), "a node's inactive values");
  if (kind == vio::MASK_AND_NO_INACTIVE_VALS || kind == vio::MASK_AND_ONE_INACTIVE_VAL ||
      kind == vio::MASK_AND_TWO_INACTIVE_VALS)
    reader.skip(valueCount / 8, "a node's selection mask");

  const bool onlyActive = (layout.compression & vio::COMPRESS_ACTIVE_MASK) && kind != vio::NO_MASK_AND_ALL_VALS;
  const std::uint64_t count = onlyActive ? activeCount : valueCount;
  if (layout.halfFloat && count == 0) return;  // HalfReader reads nothing then
  const std::uint64_t bytes = count * layout.storedBytes;
  if (layout.compression & vio::COMPRESS_BLOSC) {
    skipCompressedBlock(reader, /*blosc=*/true, bytes, decompress);
  } else if (layout.compression & vio::COMPRESS_ZIP) {
    skipCompressedBlock(reader, /*blosc=*/false, bytes, decompress);
  } else {
    reader.skip(bytes, "a node's values");
  }
}

}  // namespace levelfuse::io::detail
