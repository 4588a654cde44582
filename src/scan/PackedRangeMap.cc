// levelfuse: a range map held compressed.

#include <levelfuse/scan/PackedRangeMap.h>

#include <blosc.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace levelfuse {

namespace {

/// Blosc compresses at most about 2 GB at once: larger arrays go in chunks of this many bytes.
constexpr std::size_t kChunkBytes = std::size_t(1) << 30;
/// Zstandard's fastest level: a depth frame's readings shrink about fourfold in a few milliseconds.
constexpr int kLevel = 1;

/// The chunks of `bytes` bytes at `data`, each as its raw and packed sizes and the packed bytes.
std::vector<char> compress(const void* data, std::size_t bytes, std::size_t typeSize) {
  std::vector<char> out;
  const char* in = static_cast<const char*>(data);
  for (std::size_t done = 0; done < bytes;) {
    const std::uint64_t raw = std::min(kChunkBytes, bytes - done);
    std::vector<char> chunk(raw + BLOSC_MAX_OVERHEAD);
    const int packed = blosc_compress_ctx(kLevel, BLOSC_SHUFFLE, typeSize, raw, in + done, chunk.data(), chunk.size(),
                                          "zstd", 0, 1);
    if (packed <= 0) throw std::runtime_error("PackedRangeMap: Blosc could not compress a range map");
    const std::uint64_t sizes[2] = {raw, static_cast<std::uint64_t>(packed)};
    out.insert(out.end(), reinterpret_cast<const char*>(sizes), reinterpret_cast<const char*>(sizes) + sizeof sizes);
    out.insert(out.end(), chunk.begin(), chunk.begin() + packed);
    done += raw;
  }
  out.shrink_to_fit();
  return out;
}

/// Restores `count` values of type T from compress()'s chunks.
template <typename T>
std::vector<T> decompress(const std::vector<char>& packed, std::size_t count) {
  std::vector<T> values(count);
  char* out = reinterpret_cast<char*>(values.data());
  std::size_t at = 0, done = 0;
  while (at < packed.size()) {
    std::uint64_t sizes[2];
    std::memcpy(sizes, packed.data() + at, sizeof sizes);
    at += sizeof sizes;
    if (done + sizes[0] > count * sizeof(T) ||
        blosc_decompress_ctx(packed.data() + at, out + done, sizes[0], 1) != static_cast<int>(sizes[0]))
      throw std::runtime_error("PackedRangeMap: Blosc could not restore a range map");
    at += sizes[1];
    done += sizes[0];
  }
  if (done != count * sizeof(T)) throw std::runtime_error("PackedRangeMap: a range map restored incomplete");
  return values;
}

template <typename T>
std::vector<char> packed(std::vector<T>& values, std::size_t typeSize, std::size_t& count) {
  count = values.size();
  std::vector<char> out = compress(values.data(), values.size() * sizeof(T), typeSize);
  std::vector<T>().swap(values);
  return out;
}

}  // namespace

PackedRangeMap::PackedRangeMap(RangeMap map) : mShell(std::move(map)) {
  mReadings = packed(mShell.mReadings, sizeof(float), mReadingCount);
  mSigmas = packed(mShell.mSigmas, sizeof(float), mSigmaCount);
  mDirections = packed(mShell.mDirections, sizeof(float), mDirectionCount);
  mSamples = packed(mShell.mSamples, sizeof(double), mSampleCount);
}

RangeMap PackedRangeMap::unpack() const {
  RangeMap map = mShell;
  map.mReadings = decompress<float>(mReadings, mReadingCount);
  map.mSigmas = decompress<float>(mSigmas, mSigmaCount);
  map.mDirections = decompress<openvdb::Vec3f>(mDirections, mDirectionCount);
  map.mSamples = decompress<openvdb::Vec3d>(mSamples, mSampleCount);
  return map;
}

std::size_t PackedRangeMap::memoryBytes() const {
  return sizeof(*this) + mShell.memoryBytes() - sizeof(RangeMap) + mReadings.capacity() + mSigmas.capacity() +
         mDirections.capacity() + mSamples.capacity();
}

void PackedScans::add(RangeMap map) {
  summary.add(map);
  maps.emplace_back(std::move(map));
}

RangeMapSequence PackedScans::unpacked() const {
  return [this](const RangeMapVisitor& visit) {
    for (const PackedRangeMap& p : maps) visit(p.unpack());
  };
}

}  // namespace levelfuse
