// levelfuse: one flag per pixel of a range map, 64 to a word, with the words
// in the open so that a packed map (PackedRangeMap) compresses them as they
// are, where std::vector<bool> would be read and rebuilt flag by flag.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace levelfuse {

class PixelFlags {
 public:
  PixelFlags() = default;
  /// `count` flags, all off.
  explicit PixelFlags(std::size_t count) : mCount(count), mWords((count + 63) / 64, 0) {}
  /// `count` flags held in `words` (as words() gave them).
  PixelFlags(std::size_t count, std::vector<std::uint64_t> words) : mCount(count), mWords(std::move(words)) {}

  std::size_t size() const { return mCount; }
  bool empty() const { return mCount == 0; }
  bool operator[](std::size_t i) const { return (mWords[i >> 6] >> (i & 63)) & 1u; }
  void set(std::size_t i, bool on) {
    const std::uint64_t bit = std::uint64_t(1) << (i & 63);
    mWords[i >> 6] = on ? mWords[i >> 6] | bit : mWords[i >> 6] & ~bit;
  }
  std::vector<std::uint64_t>& words() { return mWords; }
  /// No flags, and no memory held.
  void clear() {
    mCount = 0;
    std::vector<std::uint64_t>().swap(mWords);
  }
  std::size_t memoryBytes() const { return mWords.capacity() * sizeof(std::uint64_t); }

 private:
  std::size_t mCount = 0;
  std::vector<std::uint64_t> mWords;
};

}  // namespace levelfuse
