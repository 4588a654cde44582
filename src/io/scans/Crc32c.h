// levelfuse: CRC-32C (Castagnoli), the checksum of every page of an E57 file
// (private to the readers).
#pragma once

#include <cstddef>
#include <cstdint>

namespace levelfuse::io::detail {

/// The CRC-32C of `size` bytes at `data` (reflected polynomial 0x82F63B78,
/// initial value and final xor 0xFFFFFFFF): 0xE3069283 for "123456789".
std::uint32_t crc32c(const unsigned char* data, std::size_t size);

}  // namespace levelfuse::io::detail
