// levelfuse: the readings each cell of a range map can interpolate (private
// to the data term's accumulation, which culls a map's voxels by them).
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <cmath>
#include <cstddef>
#include <memory>

namespace levelfuse::detail {

/// Per cell (i, j) of a map, between pixels i to i + 1 and j to j + 1: the
/// smallest and largest reading it may give a point, NaN where it gives none.
/// A usable cell gives the readings of its usableCellSpan (between its four
/// readings, but at a station's border); a station's cell that is not usable,
/// those of its edgeReadings. Worked out from the map when accumulation takes
/// it up, in parallel over rows of cells; the map must outlive it.
class CellSpans {
 public:
  explicit CellSpans(const RangeMap& map);

  const RangeMap& map() const { return mMap; }
  /// Whether cell (i, j) gives a reading (its span is not NaN).
  bool givesReadings(int i, int j) const { return at(i, j).lo == at(i, j).lo; }
  float lo(int i, int j) const { return at(i, j).lo; }
  float hi(int i, int j) const { return at(i, j).hi; }
  /// Whether a point at pixel coordinates (u, v) and reading coordinate z may
  /// lie within `reach` of the reading its cell gives: false only where
  /// (u, v) lies in cell (floor u, floor v) and z lies farther than `reach`
  /// (and a slack for rounding) from every reading the cell gives. The cull of
  /// a voxel before its interpolation (RangeMap::sampleLocal), which finds
  /// the same where the test says false.
  bool mayReach(double u, double v, double z, double reach) const {
    if (!(u >= 0.0) || !(v >= 0.0) || !(u < mCellsX) || !(v < mCellsY)) return true;
    const Span& s = at(static_cast<int>(u), static_cast<int>(v));
    // Far wider than the rounding of an interpolation, and of a span held as floats.
    const double slack = reach * (1.0 + 1e-6) + 1e-6 * (1.0 + std::fabs(z));
    return z >= s.lo - slack && z <= s.hi + slack;
  }

 private:
  struct Span {
    float lo, hi;
  };
  const Span& at(int i, int j) const {
    return mSpans[static_cast<std::size_t>(j) * static_cast<std::size_t>(mCellsX) + static_cast<std::size_t>(i)];
  }
  /// The spans of the cells of row j.
  void findRow(int j);

  const RangeMap& mMap;
  int mCellsX = 0, mCellsY = 0;
  /// Per cell, row by row; findRow writes every one (not zeroed first: a
  /// frame's cells are found in parallel, an allocation's zeroing is serial).
  std::unique_ptr<Span[]> mSpans;
};

}  // namespace levelfuse::detail
