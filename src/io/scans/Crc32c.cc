// levelfuse: CRC-32C, a byte at a time from a table.

#include "Crc32c.h"

#include <array>

namespace levelfuse::io::detail {

namespace {

constexpr std::uint32_t kReflectedPolynomial = 0x82F63B78u;

std::array<std::uint32_t, 256> makeTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t byte = 0; byte < 256; ++byte) {
    std::uint32_t crc = byte;
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ ((crc & 1u) ? kReflectedPolynomial : 0u);
    table[byte] = crc;
  }
  return table;
}

}  // namespace

std::uint32_t crc32c(const unsigned char* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = makeTable();
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) crc = (crc >> 8) ^ table[(crc ^ data[i]) & 0xFFu];
  return crc ^ 0xFFFFFFFFu;
}

}  // namespace levelfuse::io::detail
