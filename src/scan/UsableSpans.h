// levelfuse: the readings a range map's usable cells can interpolate, per
// block of cells (private to the data term's accumulation, which culls by
// them).
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include "CellSpans.h"

#include <vector>

namespace levelfuse::detail {

/// Per block of kBlock x kBlock cells (those whose first pixel lies in it):
/// the smallest and largest reading of its usable cells (and of a station's
/// edges extended into the others, RangeMap::edgeReadings), and the widest
/// open stretch between them that no cell's readings span (a depth
/// discontinuity's: the cells across it are not usable). Worked out from the
/// spans of the map's cells when accumulation takes it up, in parallel over
/// rows of blocks; the map must outlive it.
class UsableSpans {
 public:
  explicit UsableSpans(const CellSpans& cells);
  /// The same from the map's cells, worked out for it and let go.
  explicit UsableSpans(const RangeMap& map) : UsableSpans(CellSpans(map)) {}

  const RangeMap& map() const { return mMap; }
  /// Whether a reading interpolated in a usable cell whose corner pixel (its
  /// first) lies in the window [u0, u1] x [v0, v1] (clamped to the map; a
  /// station's border cells also stand for the border beyond them) may lie
  /// between lo and hi. A reading interpolated in a cell lies within its
  /// usableCellSpan; one extended from a station's edge, within its
  /// edgeReadings.
  bool meet(double u0, double v0, double u1, double v1, double lo, double hi) const;

  static constexpr int kBlock = 8;  ///< cells per side of a block

 private:
  /// The spans of the block in column b and row c of blocks.
  void findSpans(const CellSpans& cells, int b, int c);

  const RangeMap& mMap;
  int mBlocksX = 0, mBlocksY = 0;
  /// Per block, NaN where it has no usable cell (min, max) or no open stretch (gap).
  std::vector<float> mMin, mMax, mGapLo, mGapHi;
};

}  // namespace levelfuse::detail
