// levelfuse: a range map held compressed, for the work that must see every
// scan again after they were integrated (space carving) without holding them
// all: a 640 x 480 depth frame of a room takes about a third of its memory.
#pragma once

#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/scan/ScanSummary.h>

#include <cstddef>
#include <vector>

namespace levelfuse {

class PackedRangeMap {
 public:
  /// Takes the map and compresses its per-pixel arrays (readings, sigmas,
  /// ray directions, samples) without loss (Blosc: Zstandard on the values'
  /// bytes shuffled, so the exponents and the high bits of neighbouring
  /// readings lie together); what the map derived from them stays as it is.
  explicit PackedRangeMap(RangeMap map);

  /// The map, identical bit for bit to the one packed.
  RangeMap unpack() const;

  /// Memory held (bytes), the compressed arrays and the rest of the map.
  std::size_t memoryBytes() const;

 private:
  RangeMap mShell;  ///< the map without its per-pixel arrays
  std::vector<char> mReadings, mSigmas, mDirections, mSamples;  ///< compressed
  std::size_t mReadingCount = 0, mSigmaCount = 0, mDirectionCount = 0, mSampleCount = 0;
};

/// Scans held packed as they are read, with what a reconstruction's derived
/// settings are taken from (resolveReconstructionOptions): a folder of depth
/// frames read with io::ScanLoadOptions::take into these holds one frame
/// unpacked at a time.
struct PackedScans {
  std::vector<PackedRangeMap> maps;
  ScanSummary summary;
  /// Adds a scan: its facts to the summary, the map packed.
  void add(RangeMap map);
  /// The maps, unpacked one at a time.
  RangeMapSequence unpacked() const;
};

}  // namespace levelfuse
