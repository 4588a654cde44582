// levelfuse: the byte order of files against the machine's (private to the
// readers and writers). Each file format fixes its order (PLY and PFM say it
// in their headers, KITTI, EXR and E57 are little-endian, PNG and E57's page checksums big-endian); values
// are turned into the machine's order here and nowhere else.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace levelfuse::io::detail {

/// True on a little-endian machine.
inline bool hostIsLittleEndian() {
  const std::uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

/// Turns the `count` bytes of one value at `bytes`, stored little-endian if
/// `littleEndian` (else big-endian), into the machine's order, in place.
inline void toHostOrder(unsigned char* bytes, std::size_t count, bool littleEndian) {
  if (littleEndian != hostIsLittleEndian()) std::reverse(bytes, bytes + count);
}

/// The same turn, from the machine's order to the file's (it is its own inverse).
inline void toFileOrder(unsigned char* bytes, std::size_t count, bool littleEndian) {
  toHostOrder(bytes, count, littleEndian);
}

/// The unsigned 32-bit value stored little-endian at `bytes`.
inline std::uint32_t littleEndian32(const unsigned char* bytes) {
  return std::uint32_t(bytes[0]) | std::uint32_t(bytes[1]) << 8 | std::uint32_t(bytes[2]) << 16 |
         std::uint32_t(bytes[3]) << 24;
}

/// The unsigned 32-bit value stored big-endian at `bytes`.
inline std::uint32_t bigEndian32(const unsigned char* bytes) {
  return std::uint32_t(bytes[0]) << 24 | std::uint32_t(bytes[1]) << 16 | std::uint32_t(bytes[2]) << 8 |
         std::uint32_t(bytes[3]);
}

/// The unsigned value of `count` bytes (at most 8) stored little-endian at `bytes`.
inline std::uint64_t littleEndianUnsigned(const unsigned char* bytes, int count) {
  std::uint64_t value = 0;
  for (int i = count - 1; i >= 0; --i) value = value << 8 | bytes[i];
  return value;
}

/// The float32 stored little-endian at `bytes`.
inline float littleEndianFloat(const unsigned char* bytes) {
  const std::uint32_t word = littleEndian32(bytes);
  float value = 0.0f;
  std::memcpy(&value, &word, sizeof value);
  return value;
}

}  // namespace levelfuse::io::detail
