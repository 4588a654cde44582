// Arrays compressed as their scalars' bytes shuffled and Zstandard: restored
// bit for bit across the blocks they are shuffled in, smaller than they were
// where neighbouring values are alike, and refused when cut short.

#include "../../src/scan/ShuffledZstd.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

namespace levelfuse::detail {
namespace {

/// A smooth run of doubles with a little noise: a million bytes, four blocks and a part.
std::vector<double> smoothDoubles() {
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 1e-6);
  std::vector<double> values(125'003);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 2.5 + 1e-4 * static_cast<double>(i % 640) + noise(random);
  return values;
}

TEST(ShuffledZstd, RestoresEveryByteAcrossItsBlocks) {
  const std::vector<double> values = smoothDoubles();
  const std::vector<char> packed = shuffleAndCompress(values.data(), values.size() * sizeof(double), sizeof(double));
  EXPECT_LT(packed.size(), values.size() * sizeof(double) * 3 / 4);
  std::vector<double> restored(values.size());
  decompressAndUnshuffle(packed, restored.data(), restored.size() * sizeof(double), sizeof(double));
  EXPECT_EQ(std::memcmp(values.data(), restored.data(), values.size() * sizeof(double)), 0);
}

TEST(ShuffledZstd, RestoresScalarsOfEachSizeItPacks) {
  std::vector<std::uint16_t> steps(300'001);
  for (std::size_t i = 0; i < steps.size(); ++i) steps[i] = static_cast<std::uint16_t>(1500 + (i * 7) % 300);
  for (const std::size_t scalar : {1, 2}) {
    const std::vector<char> packed = shuffleAndCompress(steps.data(), steps.size() * 2, scalar);
    std::vector<std::uint16_t> restored(steps.size());
    decompressAndUnshuffle(packed, restored.data(), restored.size() * 2, scalar);
    EXPECT_EQ(restored, steps) << scalar;
  }
  EXPECT_TRUE(shuffleAndCompress(steps.data(), 0, 2).empty());
  EXPECT_THROW(shuffleAndCompress(steps.data(), 6, 4), std::invalid_argument);
}

TEST(ShuffledZstd, BytesCutShortOrTooFewAreRefused) {
  const std::vector<double> values = smoothDoubles();
  const std::size_t bytes = values.size() * sizeof(double);
  const std::vector<char> packed = shuffleAndCompress(values.data(), bytes, sizeof(double));
  std::vector<double> restored(values.size());
  const std::vector<char> cut(packed.begin(), packed.begin() + static_cast<std::ptrdiff_t>(packed.size() / 2));
  EXPECT_THROW(decompressAndUnshuffle(cut, restored.data(), bytes, sizeof(double)), std::runtime_error);
  // Asked for fewer bytes than the frame holds: something is left over.
  EXPECT_THROW(decompressAndUnshuffle(packed, restored.data(), bytes - 8 * sizeof(double), sizeof(double)),
               std::runtime_error);
}

}  // namespace
}  // namespace levelfuse::detail
