// levelfuse: an E57 compressed vector's bytestreams, read and decoded.

#include "E57Bytestreams.h"

#include "../ByteOrder.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/MemoryBudget.h>

#include <algorithm>
#include <cstring>

namespace levelfuse::io {

namespace {

constexpr std::size_t kSectionHeaderBytes = 32;
constexpr unsigned char kCompressedVectorSection = 1;
constexpr unsigned char kIndexPacket = 0, kDataPacket = 1, kEmptyPacket = 2;
constexpr std::size_t kDataPacketHeaderBytes = 6;

/// Where a compressed vector's packets lie, logical offsets.
struct SectionExtent {
  std::uint64_t firstPacket = 0, end = 0;
};

SectionExtent readSectionHeader(E57PagedFile& file, const E57PointRecords& records, const std::string& what) {
  const std::uint64_t start = file.logicalOffset(records.fileOffset, "the section of " + what);
  unsigned char header[kSectionHeaderBytes];
  file.read(start, kSectionHeaderBytes, header, what);
  if (header[0] != kCompressedVectorSection)
    throw InputError(file.path(), what + ": the section at byte " + std::to_string(records.fileOffset) + " has id " +
                                      std::to_string(header[0]) + ", not a compressed vector's (1)");
  const std::uint64_t length = detail::littleEndianUnsigned(header + 8, 8);
  if (length < kSectionHeaderBytes || length > file.logicalLength() - start)
    throw InputError(file.path(), what + ": its section declares " + std::to_string(length) +
                                      " bytes, which the file does not hold after its start");
  SectionExtent extent;
  extent.end = start + length;
  extent.firstPacket = file.logicalOffset(detail::littleEndianUnsigned(header + 16, 8), what + "' first packet");
  if (extent.firstPacket < start + kSectionHeaderBytes || extent.firstPacket >= extent.end)
    throw InputError(file.path(), what + ": its first packet is placed outside its section");
  return extent;
}

/// The bytes each field's bytestream holds for all the records, checked
/// against the section's length and the memory budget.
std::vector<std::uint64_t> streamBytes(const E57PointRecords& records, const SectionExtent& extent,
                                       const std::string& path, const std::string& what,
                                       const MemoryBudget& budget) {
  const std::uint64_t sectionBytes = extent.end - extent.firstPacket;
  std::vector<std::uint64_t> bytes;
  std::uint64_t total = 0;
  for (const E57Field& field : records.fields) {
    const int bits = field.bits();
    if (bits > 0 && records.recordCount > sectionBytes * 8 / static_cast<std::uint64_t>(bits))
      throw InputError(path, what + " declare " + std::to_string(records.recordCount) + " records, whose field " +
                                 quote(field.name) + " alone needs more than the " + std::to_string(sectionBytes) +
                                 " bytes of their section");
    bytes.push_back((records.recordCount * static_cast<std::uint64_t>(bits) + 7) / 8);
    total += bytes.back();
  }
  if (total > sectionBytes)
    throw InputError(path, what + " declare " + std::to_string(records.recordCount) + " records of " +
                               std::to_string(total) + " bytes, more than the " + std::to_string(sectionBytes) +
                               " bytes of their section");
  requireMemory(budget, path, static_cast<double>(total), what, "split the file into smaller scans");
  return bytes;
}

}  // namespace

std::uint64_t unpackBits(const std::vector<unsigned char>& bytes, std::uint64_t bitOffset, int bits) {
  if (bits == 0) return 0;
  const std::uint64_t first = bitOffset / 8;
  const int shift = static_cast<int>(bitOffset % 8);
  unsigned char window[9] = {};
  if (first < bytes.size())
    std::memcpy(window, bytes.data() + first, static_cast<std::size_t>(std::min<std::uint64_t>(9, bytes.size() - first)));
  std::uint64_t value = detail::littleEndianUnsigned(window, 8) >> shift;
  if (shift + bits > 64) value |= static_cast<std::uint64_t>(window[8]) << (64 - shift);
  return bits == 64 ? value : value & ((std::uint64_t(1) << bits) - 1);
}

E57Bytestreams::E57Bytestreams(E57PagedFile& file, const E57PointRecords& records, const std::string& what,
                               const MemoryBudget& budget, const Interrupter& interrupter)
    : mRecords(records) {
  const SectionExtent extent = readSectionHeader(file, records, what);
  const std::vector<std::uint64_t> wanted = streamBytes(records, extent, file.path(), what, budget);
  mStreams.resize(records.fields.size());
  for (std::size_t i = 0; i < wanted.size(); ++i) mStreams[i].reserve(static_cast<std::size_t>(wanted[i]));
  const auto complete = [&] {
    for (std::size_t i = 0; i < wanted.size(); ++i)
      if (mStreams[i].size() < wanted[i]) return false;
    return true;
  };
  std::vector<unsigned char> packet;
  for (std::uint64_t at = extent.firstPacket; !complete(); ) {
    checkInterrupter(interrupter);
    const std::string where = what + ": the packet at logical byte " + std::to_string(at);
    if (at + 4 > extent.end)
      throw InputError(file.path(), what + ": the section ends before the bytestreams hold every record "
                                           "(truncated, or a record count that is too large)");
    unsigned char head[4];
    file.read(at, 4, head, where);
    const std::uint64_t length = detail::littleEndianUnsigned(head + 2, 2) + 1;
    if (length > extent.end - at) throw InputError(file.path(), where + " runs past the end of its section");
    if (head[0] == kDataPacket) {
      packet.resize(static_cast<std::size_t>(length));
      file.read(at, packet.size(), packet.data(), where);
      const std::size_t streams = packet.size() >= kDataPacketHeaderBytes ? detail::littleEndianUnsigned(packet.data() + 4, 2) : 0;
      if (streams != mStreams.size())
        throw InputError(file.path(), where + " holds " + std::to_string(streams) + " bytestreams for " +
                                          std::to_string(mStreams.size()) + " fields");
      std::size_t offset = kDataPacketHeaderBytes + 2 * streams;
      if (offset > packet.size()) throw InputError(file.path(), where + " is too short for its bytestream lengths");
      for (std::size_t i = 0; i < streams; ++i) {
        const std::size_t bytes = detail::littleEndianUnsigned(packet.data() + kDataPacketHeaderBytes + 2 * i, 2);
        if (bytes > packet.size() - offset)
          throw InputError(file.path(), where + ": its bytestream " + std::to_string(i) + " runs past the packet");
        const std::size_t kept = static_cast<std::size_t>(
            std::min<std::uint64_t>(bytes, wanted[i] - std::min<std::uint64_t>(wanted[i], mStreams[i].size())));
        mStreams[i].insert(mStreams[i].end(), packet.begin() + static_cast<std::ptrdiff_t>(offset),
                           packet.begin() + static_cast<std::ptrdiff_t>(offset + kept));
        offset += bytes;
      }
    } else if (head[0] != kIndexPacket && head[0] != kEmptyPacket) {
      throw InputError(file.path(), where + " is of type " + std::to_string(head[0]) +
                                        " (expected 0, 1 or 2: index, data or empty)");
    }
    at += length;
  }
}

std::uint64_t E57Bytestreams::packedBits(std::size_t field, std::uint64_t record) const {
  const int bits = mRecords.fields[field].bits();
  return unpackBits(mStreams[field], record * static_cast<std::uint64_t>(bits), bits);
}

std::int64_t E57Bytestreams::integer(std::size_t field, std::uint64_t record) const {
  return static_cast<std::int64_t>(packedBits(field, record) + static_cast<std::uint64_t>(mRecords.fields[field].minimum));
}

double E57Bytestreams::value(std::size_t field, std::uint64_t record) const {
  const E57Field& f = mRecords.fields[field];
  if (f.type == E57Field::Type::kFloat) {
    const std::uint64_t word = packedBits(field, record);
    if (f.doublePrecision) {
      double d;
      std::memcpy(&d, &word, sizeof d);
      return d;
    }
    const std::uint32_t single = static_cast<std::uint32_t>(word);
    float s;
    std::memcpy(&s, &single, sizeof s);
    return s;
  }
  const double stored = static_cast<double>(integer(field, record));
  return f.type == E57Field::Type::kScaledInteger ? stored * f.scale + f.offset : stored;
}

}  // namespace levelfuse::io
