// levelfuse: what every binning of a scanner's points into a spherical grid
// does with the binned scan.

#include "BinnedScan.h"

#include <cmath>
#include <cstddef>
#include <utility>

namespace levelfuse::detail {

namespace {

/// The slope of the readings across a pixel from its two neighbours along
/// one direction, each measured between the points' own places: the smaller
/// of the two where they agree in sign, else 0 (minmod). A depth step on one
/// side, or a thin structure between two, then bends no reading.
double limitedSlope(double before, double after) {
  if (before * after <= 0.0) return 0.0;
  return std::fabs(before) < std::fabs(after) ? before : after;
}

}  // namespace

void centreReadingsOnPixels(BinnedScan& scan) {
  const long width = scan.width, height = scan.height;
  const long columns = scan.closedTurn ? width - 1 : width;  // distinct columns
  const std::vector<float> ranges = scan.ranges;
  const auto at = [&](long u, long v) {
    return static_cast<std::size_t>(v) * static_cast<std::size_t>(width) + static_cast<std::size_t>(u);
  };
  const auto valid = [&](std::size_t i) { return ranges[i] == ranges[i]; };
  // The reading's change per pixel from the point of pixel a to that of b,
  // b one pixel after a along a direction whose offsets are `offsets`.
  const auto slope = [&](std::size_t a, std::size_t b, const std::vector<float>& offsets) {
    return (ranges[b] - ranges[a]) / (1.0 + offsets[b] - offsets[a]);
  };
  for (long v = 0; v < height; ++v)
    for (long u = 0; u < columns; ++u) {
      const std::size_t i = at(u, v);
      if (!valid(i)) continue;
      double centred = ranges[i];
      const long left = u > 0 ? u - 1 : (scan.closedTurn ? columns - 1 : -1);
      const long right = u + 1 < columns ? u + 1 : (scan.closedTurn ? 0 : -1);
      if (left >= 0 && right >= 0 && valid(at(left, v)) && valid(at(right, v)))
        centred -= scan.columnOffsets[i] * limitedSlope(slope(at(left, v), i, scan.columnOffsets),
                                                        slope(i, at(right, v), scan.columnOffsets));
      if (v > 0 && v + 1 < height && valid(at(u, v - 1)) && valid(at(u, v + 1)))
        centred -= scan.rowOffsets[i] * limitedSlope(slope(at(u, v - 1), i, scan.rowOffsets),
                                                     slope(i, at(u, v + 1), scan.rowOffsets));
      scan.ranges[i] = static_cast<float>(centred);
    }
}

void closeTheTurn(BinnedScan& scan) {
  if (!scan.closedTurn) return;
  const std::size_t width = static_cast<std::size_t>(scan.width);
  for (std::size_t v = 0; v < static_cast<std::size_t>(scan.height); ++v) {
    scan.ranges[v * width + width - 1] = scan.ranges[v * width];
    if (!scan.colours.empty()) scan.colours[v * width + width - 1] = scan.colours[v * width];
  }
}

RangeMap mapOfBinnedScan(BinnedScan scan, const openvdb::math::Mat4d& scannerToWorld, double sigma, std::string name) {
  RangeMap map = RangeMap::spherical(scan.width, scan.height, std::move(scan.ranges), scan.grid, scannerToWorld, sigma,
                                     std::move(name));
  map.setColours(std::move(scan.colours));
  return map;
}

RangeMap mapOfBinnedScan(BinnedScan scan, const openvdb::math::Mat4d& scannerToWorld, const DepthNoise& noise,
                         std::string name) {
  RangeMap map = RangeMap::spherical(scan.width, scan.height, std::move(scan.ranges), scan.grid, scannerToWorld, noise,
                                     std::move(name));
  map.setColours(std::move(scan.colours));
  return map;
}

}  // namespace levelfuse::detail
