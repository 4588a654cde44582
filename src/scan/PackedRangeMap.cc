// levelfuse: a range map held compressed.

#include <levelfuse/scan/PackedRangeMap.h>

#include <levelfuse/core/MadeAhead.h>

#include "ShuffledZstd.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

namespace levelfuse {

namespace {

using Array = PackedRangeMap::Array;

/// Restores `count` values of type T from the array's bytes.
template <typename T>
std::vector<T> decompress(const Array& packed, std::size_t count) {
  std::vector<T> values(count);
  detail::decompressAndUnshuffle(packed.bytes, values.data(), count * sizeof(T), packed.scalarSize);
  return values;
}

/// Compresses `values` (shuffled by their scalar's size) and lets them go.
template <typename T, typename Scalar = T>
Array packArray(std::vector<T>& values) {
  Array packed{detail::shuffleAndCompress(values.data(), values.size() * sizeof(T), sizeof(Scalar)), values.size(),
               sizeof(Scalar)};
  std::vector<T>().swap(values);
  return packed;
}

template <typename T>
std::vector<T> unpackArray(const Array& packed) {
  return decompress<T>(packed, packed.count);
}

/// Flags, compressed as their words' bytes; the flags are let go.
Array packFlags(PixelFlags& flags) {
  Array packed = packArray<std::uint64_t, std::uint8_t>(flags.words());
  packed.count = flags.size();
  flags.clear();
  return packed;
}

PixelFlags unpackFlags(const Array& packed) {
  return PixelFlags(packed.count, decompress<std::uint64_t>(packed, (packed.count + 63) / 64));
}

/// The NaN a map holds where it has no reading (RangeMap::finish).
const float kNoReading = std::numeric_limits<float>::quiet_NaN();
/// Readings held as whole steps: 0 for no reading, then 1 to this many steps.
constexpr double kMostSteps = 65535.0;

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

float readingOfSteps(std::uint16_t steps, double step) {
  return steps == 0 ? kNoReading : static_cast<float>(static_cast<double>(steps) * step);
}

/// Whether `k` whole steps restore reading `r` bit for bit.
bool restores(double k, float r, double step) {
  return k >= 0.0 && k <= kMostSteps && sameBits(readingOfSteps(static_cast<std::uint16_t>(k), step), r);
}

/// Each reading as its number of steps, if every one is exactly that (as a
/// 16-bit depth image's readings are); empty if any is not. At most one
/// number of steps restores a reading (steps differ by more than a float's
/// precision below 2^16 of them), so the product with the step's inverse,
/// rounded, is tried before the division.
std::vector<std::uint16_t> stepsOfReadings(const std::vector<float>& readings, double step) {
  if (!(step > 0.0)) return {};
  const double perStep = 1.0 / step;
  std::vector<std::uint16_t> steps(readings.size());
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const float r = readings[i];
    if (!(r == r)) {
      steps[i] = 0;
      continue;
    }
    const double guess = r * perStep + 0.5;
    double k = guess > 0.0 && guess < kMostSteps + 1.0 ? static_cast<double>(static_cast<int>(guess)) : -1.0;
    if (!restores(k, r, step)) k = std::nearbyint(r / step);
    if (!restores(k, r, step)) return {};
    steps[i] = static_cast<std::uint16_t>(k);
  }
  return steps;
}

}  // namespace

PackedRangeMap::PackedRangeMap(RangeMap map) : mShell(std::move(map)) {
  std::vector<std::uint16_t> steps = stepsOfReadings(mShell.mReadings, mShell.readingStep());
  mReadingsAsSteps = !steps.empty();
  if (mReadingsAsSteps) {
    mReadings = packArray(steps);
    std::vector<float>().swap(mShell.mReadings);
  } else {
    mReadings = packArray(mShell.mReadings);
  }
  mSigmas = packArray(mShell.mSigmas);
  mDirections = packArray<openvdb::Vec3f, float>(mShell.mDirections);
  mSamples = packArray<openvdb::Vec3d, double>(mShell.mSamples);
  mColours = packArray<Rgb8, std::uint8_t>(mShell.mColours);
  mBlockMin = packArray(mShell.mBlockMin);
  mBlockMax = packArray(mShell.mBlockMax);
  mBlockComplete = packArray(mShell.mBlockComplete);
  mUsableCells = packFlags(mShell.mUsableCell);
  mMisses = packFlags(mShell.mMisses);
}

RangeMap PackedRangeMap::unpack() const {
  RangeMap map = mShell;
  if (mReadingsAsSteps) {
    const std::vector<std::uint16_t> steps = unpackArray<std::uint16_t>(mReadings);
    map.mReadings.resize(steps.size());
    for (std::size_t i = 0; i < steps.size(); ++i) map.mReadings[i] = readingOfSteps(steps[i], map.readingStep());
  } else {
    map.mReadings = unpackArray<float>(mReadings);
  }
  map.mSigmas = unpackArray<float>(mSigmas);
  map.mDirections = unpackArray<openvdb::Vec3f>(mDirections);
  map.mSamples = unpackArray<openvdb::Vec3d>(mSamples);
  map.mColours = unpackArray<Rgb8>(mColours);
  map.mBlockMin = unpackArray<float>(mBlockMin);
  map.mBlockMax = unpackArray<float>(mBlockMax);
  map.mBlockComplete = unpackArray<std::uint8_t>(mBlockComplete);
  map.mUsableCell = unpackFlags(mUsableCells);
  map.mMisses = unpackFlags(mMisses);
  return map;
}

void PackedRangeMap::letSamplesGo() {
  if (mSamples.count == 0) return;
  mShell.mSamplesLetGo = mSamples.count;
  mSamples = Array();
}

std::size_t PackedRangeMap::memoryBytes() const {
  std::size_t bytes = sizeof(*this) + mShell.memoryBytes() - sizeof(RangeMap);
  for (const Array* a : {&mReadings, &mSigmas, &mDirections, &mSamples, &mColours, &mBlockMin, &mBlockMax, &mBlockComplete,
                         &mUsableCells, &mMisses})
    bytes += a->bytes.capacity();
  return bytes;
}

void PackedScans::add(RangeMap map) {
  summary.add(map);
  maps.emplace_back(std::move(map));
}

void visitUnpacked(const std::vector<PackedRangeMap>& maps, const RangeMapVisitor& visit) {
  visitUnpacked(maps, 0, [&](std::size_t, const RangeMap& map) { visit(map); });
}

void visitUnpacked(const std::vector<PackedRangeMap>& maps, std::size_t first, const NumberedRangeMapVisitor& visit) {
  if (first >= maps.size()) return;
  takeMadeAhead<RangeMap>(
      maps.size() - first, [&](std::size_t i) { return maps[first + i].unpack(); },
      [&](std::size_t i, RangeMap&& map) { visit(first + i, map); });
}

void PackedScans::letSamplesGo() {
  for (PackedRangeMap& map : maps) map.letSamplesGo();
}

RangeMapSequence PackedScans::unpacked() const {
  return [this](const RangeMapVisitor& visit) { visitUnpacked(maps, visit); };
}

}  // namespace levelfuse
