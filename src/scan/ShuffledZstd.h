// levelfuse: arrays compressed without loss as their scalars' bytes shuffled
// and Zstandard (private to PackedRangeMap).
#pragma once

#include <cstddef>
#include <vector>

namespace levelfuse::detail {

/// The `bytes` bytes at `data`, values of scalars of `scalarSize` bytes,
/// compressed: a block at a time, each byte of every scalar gathered with the
/// same byte of the others (the exponents and high bits of neighbouring
/// values together), at Zstandard's fastest level, with a compression context
/// kept per thread (making one costs more than compressing a small array).
std::vector<char> shuffleAndCompress(const void* data, std::size_t bytes, std::size_t scalarSize);

/// Restores `bytes` bytes into `out` from shuffleAndCompress's result for the
/// same `scalarSize`; throws std::runtime_error if they do not restore to
/// exactly that many.
void decompressAndUnshuffle(const std::vector<char>& packed, void* out, std::size_t bytes, std::size_t scalarSize);

}  // namespace levelfuse::detail
