// levelfuse: the records of an E57 compressed vector (private to the E57
// reader): its binary section's data packets gathered into one bytestream per
// field, and each record's values decoded from them (bit packing: integers
// as value - minimum in the field's bits, least significant bit first;
// floats as IEEE 754 little-endian).
#pragma once

#include "E57PagedFile.h"
#include "E57Xml.h"

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/core/MemoryBudget.h>

#include <cstdint>
#include <string>
#include <vector>

namespace levelfuse::io {

class E57Bytestreams {
 public:
  /// Reads the bytestreams of `records` from `file`; `what` names them in
  /// messages ("the points of scan 1"). `interrupter` is asked before each
  /// packet. Throws InputError naming the file for a section that is not a
  /// compressed vector's or lies beyond the file, records that need more
  /// bytes than the section holds or more memory than `budget` allows
  /// (checked before anything is allocated), a packet of an unknown type or
  /// that runs past its section, a data packet with another number of
  /// bytestreams than the fields, and bytestreams that end before the last
  /// record.
  E57Bytestreams(E57PagedFile& file, const E57PointRecords& records, const std::string& what,
                 const MemoryBudget& budget, const Interrupter& interrupter);

  /// Field `field`'s value in record `record` (a scaled integer scaled).
  double value(std::size_t field, std::uint64_t record) const;
  /// The integer stored for an integer or scaled-integer field (unscaled).
  std::int64_t integer(std::size_t field, std::uint64_t record) const;

 private:
  std::uint64_t packedBits(std::size_t field, std::uint64_t record) const;

  const E57PointRecords& mRecords;
  std::vector<std::vector<unsigned char>> mStreams;
};

/// The `bits`-bit value (0 to 64 bits) from bit `bitOffset` of `bytes`,
/// least significant bit first; bytes beyond the end read as 0.
std::uint64_t unpackBits(const std::vector<unsigned char>& bytes, std::uint64_t bitOffset, int bits);

}  // namespace levelfuse::io
