// levelfuse: a range map held compressed, for the work that must see every
// scan again after they were integrated (space carving) without holding them
// all: a 640 x 480 depth frame of a room takes about a seventh of its memory.
#pragma once

#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/scan/ScanSummary.h>

#include <cstddef>
#include <vector>

namespace levelfuse {

class PackedRangeMap {
 public:
  /// Takes the map and compresses its per-pixel arrays without loss
  /// (Zstandard on the values' bytes shuffled, so the exponents and the high
  /// bits of neighbouring values lie together): the readings, as 16-bit
  /// integers when they are whole multiples of the map's reading step (a
  /// depth image's), the sigmas, ray directions, samples and colours, and what the
  /// map derived per pixel and per block (usable cells, misses, reading
  /// bounds).
  explicit PackedRangeMap(RangeMap map);

  /// The map, identical bit for bit to the one packed.
  RangeMap unpack() const;

  /// The map without its per-pixel arrays (no readings): its kind, size,
  /// projection, pose and name, what RangeMap::mayBeSeenIn asks.
  const RangeMap& shell() const { return mShell; }

  /// Lets go of the measured points (RangeMap::letSamplesGo): unpack()
  /// then gives the map without them, their count kept.
  void letSamplesGo();

  /// Memory held (bytes), the compressed arrays and the rest of the map.
  std::size_t memoryBytes() const;

  /// True if the readings are held as 16-bit multiples of the reading step.
  bool readingsAsSteps() const { return mReadingsAsSteps; }

  /// One compressed array: its bytes, how many values it restores to, and
  /// the size of the scalars whose bytes were shuffled.
  struct Array {
    std::vector<char> bytes;
    std::size_t count = 0;
    std::size_t scalarSize = 1;
  };

 private:
  RangeMap mShell;  ///< the map without its per-pixel arrays
  Array mReadings, mSigmas, mDirections, mSamples, mColours, mBlockMin, mBlockMax, mBlockComplete, mUsableCells, mMisses;
  bool mReadingsAsSteps = false;
};

/// Calls `visit` with each of `maps` unpacked, in order, from the calling
/// thread: they are unpacked a batch at a time in parallel (twice as many as
/// there are threads), the next batch while the maps of the last are visited
/// (no more than two batches are held unpacked at once).
void visitUnpacked(const std::vector<PackedRangeMap>& maps, const RangeMapVisitor& visit);
/// The same from map `first` on, each visited with its index in `maps`.
void visitUnpacked(const std::vector<PackedRangeMap>& maps, std::size_t first, const NumberedRangeMapVisitor& visit);

/// Scans held packed as they are read, with what a reconstruction's derived
/// settings are taken from (resolveReconstructionSettings): a folder of depth
/// frames read with io::ScanLoadOptions::take into these holds one frame
/// unpacked at a time.
struct PackedScans {
  std::vector<PackedRangeMap> maps;
  ScanSummary summary;
  /// Adds a scan: its facts to the summary, the map packed.
  void add(RangeMap map);
  /// The maps, unpacked a few at a time (visitUnpacked).
  RangeMapSequence unpacked() const;
  /// Every map's measured points let go (PackedRangeMap::letSamplesGo), for a
  /// process that will not measure the fit; the summary is unchanged.
  void letSamplesGo();
};

}  // namespace levelfuse
