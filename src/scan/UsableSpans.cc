// levelfuse: the readings a range map's usable cells can interpolate, per block of cells.

#include "UsableSpans.h"

#include <levelfuse/core/Parallel.h>

#include "ClampedIndex.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace levelfuse::detail {

UsableSpans::UsableSpans(const CellSpans& cells) : mMap(cells.map()) {
  const RangeMap& map = mMap;
  const int cellsX = map.width() - 1, cellsY = map.height() - 1;
  mBlocksX = (cellsX + kBlock - 1) / kBlock;
  mBlocksY = (cellsY + kBlock - 1) / kBlock;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::size_t blocks = static_cast<std::size_t>(mBlocksX) * static_cast<std::size_t>(mBlocksY);
  mMin.assign(blocks, nan);
  mMax.assign(blocks, nan);
  mGapLo.assign(blocks, nan);
  mGapHi.assign(blocks, nan);
  parallelFor(static_cast<std::size_t>(mBlocksY), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c)
      for (int b = 0; b < mBlocksX; ++b) findSpans(cells, b, static_cast<int>(c));
  });
}

void UsableSpans::findSpans(const CellSpans& cells, int b, int c) {
  struct Span {
    float lo, hi;
  };
  // Neighbouring cells of a row share two readings, so a run of usable cells
  // spans one stretch: a span per run.
  // At most a run in every other cell of each row, and a station's edges in the others.
  std::array<Span, kBlock * kBlock> spans;
  std::size_t count = 0;
  const int i0 = b * kBlock, i1 = std::min((b + 1) * kBlock, mMap.width() - 1);
  for (int j = c * kBlock; j < std::min((c + 1) * kBlock, mMap.height() - 1); ++j) {
    bool inRun = false;
    for (int i = i0; i < i1; ++i) {
      if (!mMap.cellUsable(i, j)) {
        inRun = false;
        if (cells.givesReadings(i, j)) spans[count++] = {cells.lo(i, j), cells.hi(i, j)};  // a station's edge
        continue;
      }
      const float lo = cells.lo(i, j), hi = cells.hi(i, j);
      if (!inRun) spans[count++] = {lo, hi};
      spans[count - 1].lo = std::min(spans[count - 1].lo, lo);
      spans[count - 1].hi = std::max(spans[count - 1].hi, hi);
      inRun = true;
    }
  }
  if (count == 0) return;
  std::sort(spans.begin(), spans.begin() + count, [](const Span& one, const Span& other) { return one.lo < other.lo; });
  const std::size_t at = static_cast<std::size_t>(c) * mBlocksX + b;
  float reached = spans[0].hi;  // the largest reading of the spans so far
  for (std::size_t s = 0; s < count; ++s) {
    if (spans[s].lo > reached && !(spans[s].lo - reached <= mGapHi[at] - mGapLo[at])) {
      mGapLo[at] = reached;
      mGapHi[at] = spans[s].lo;
    }
    reached = std::max(reached, spans[s].hi);
  }
  mMin[at] = spans[0].lo;
  mMax[at] = reached;
}

bool UsableSpans::meet(double u0, double v0, double u1, double v1, double lo, double hi) const {
  const int width = mMap.width(), height = mMap.height();
  const double border = mMap.borderReach();
  if (!(u1 >= -border) || !(v1 >= -border) || !(u0 < width - 1 + border) || !(v0 < height - 1 + border)) return false;
  const int b0 = clampedIndex(std::floor(u0), width - 2) / kBlock, b1 = clampedIndex(std::floor(u1), width - 2) / kBlock;
  const int c0 = clampedIndex(std::floor(v0), height - 2) / kBlock;
  const int c1 = clampedIndex(std::floor(v1), height - 2) / kBlock;
  for (int c = c0; c <= c1; ++c)
    for (int b = b0; b <= b1; ++b) {
      const std::size_t at = static_cast<std::size_t>(c) * mBlocksX + b;
      if (!(hi >= mMin[at] && lo <= mMax[at])) continue;  // also without usable cells (NaN)
      if (lo > mGapLo[at] && hi < mGapHi[at]) continue;    // within the stretch no cell spans
      return true;
    }
  return false;
}

}  // namespace levelfuse::detail
