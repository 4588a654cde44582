// levelfuse: what a reconstruction's derived settings are taken from,
// gathered scan by scan, so that scans integrated one at a time and released
// give the settings that the same scans held together give.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <openvdb/math/BBox.h>

#include <cstddef>
#include <vector>

namespace levelfuse {

class ScanSummary {
 public:
  ScanSummary() = default;
  /// The summary of `maps`.
  explicit ScanSummary(const std::vector<RangeMap>& maps);

  /// Adds one scan.
  void add(const RangeMap& map);
  /// Adds every scan of `other`: the summary of both sets of scans, whatever
  /// their order (the medians are of the values, the box is the union).
  void add(const ScanSummary& other);

  /// The summary as numbers, e.g. to send to another process, and back
  /// (fromNumbers(s.numbers()) is s); fromNumbers throws std::invalid_argument
  /// for numbers that are no summary's.
  std::vector<double> numbers() const;
  static ScanSummary fromNumbers(const std::vector<double>& numbers);

  std::size_t scans() const { return mSigmas.size(); }
  /// Readings over all scans.
  std::size_t readings() const { return mReadings; }
  /// Points the scanners measured (RangeMap::sampleCount) over all scans.
  std::size_t points() const { return mPoints; }
  /// World box of the readings.
  const openvdb::BBoxd& bounds() const { return mBounds; }
  /// The median of the scans' typical distance between neighbouring rays
  /// (RangeMap::typicalRaySpacing); 0 without scans.
  double medianRaySpacing() const;
  /// The median of the scans' noise sigma; 0 without scans.
  double medianSigma() const;
  /// True when every scan is of a scene around its scanner
  /// (RangeMap::ofAScene: depth frames, stations and LiDAR sweeps): the
  /// surface is a scene seen from inside (a room, a desk, a street) rather
  /// than an object seen from around it.
  bool aScene() const { return !mSigmas.empty() && mScenes == mSigmas.size(); }
  /// How many scans carry colour (RangeMap::hasColours).
  std::size_t colouredScans() const { return mColoured; }

 private:
  std::vector<double> mRaySpacings, mSigmas;
  std::size_t mReadings = 0, mPoints = 0, mScenes = 0, mColoured = 0;
  openvdb::BBoxd mBounds;
};

}  // namespace levelfuse
