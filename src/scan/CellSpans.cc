// levelfuse: the readings each cell of a range map can interpolate.

#include "CellSpans.h"

#include <levelfuse/core/Parallel.h>

#include <algorithm>
#include <limits>

namespace levelfuse::detail {

CellSpans::CellSpans(const RangeMap& map) : mMap(map), mCellsX(map.width() - 1), mCellsY(map.height() - 1) {
  mSpans.reset(new Span[static_cast<std::size_t>(mCellsX) * static_cast<std::size_t>(mCellsY)]);
  constexpr std::size_t kRowsPerTask = 8;
  parallelFor(static_cast<std::size_t>(mCellsY), kRowsPerTask, [&](std::size_t begin, std::size_t end) {
    for (std::size_t j = begin; j < end; ++j) findRow(static_cast<int>(j));
  });
}

void CellSpans::findRow(int j) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Only a station's cells reach beyond their readings: at its border, and
  // from its edges into the cells that are not usable.
  const bool station = mMap.borderReach() > 0.0;
  const bool borderRow = station && (j == 0 || j + 1 == mCellsY);
  Span* row = mSpans.get() + static_cast<std::size_t>(j) * static_cast<std::size_t>(mCellsX);
  for (int i = 0; i < mCellsX; ++i) {
    Span& s = row[i];
    if (!mMap.cellUsable(i, j)) {
      if (!station || !mMap.edgeReadings(i, j, s.lo, s.hi)) s.lo = s.hi = nan;
      continue;
    }
    if (borderRow || (station && (i == 0 || i + 1 == mCellsX))) {
      mMap.usableCellSpan(i, j, s.lo, s.hi);
      continue;
    }
    // usableCellSpan's corners, whose bilinear readings are the readings themselves.
    const float r00 = mMap.reading(i, j), r10 = mMap.reading(i + 1, j);
    const float r01 = mMap.reading(i, j + 1), r11 = mMap.reading(i + 1, j + 1);
    s.lo = std::min(std::min(r00, r10), std::min(r01, r11));
    s.hi = std::max(std::max(r00, r10), std::max(r01, r11));
  }
}

}  // namespace levelfuse::detail
