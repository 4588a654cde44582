// levelfuse: the pixels a spherical grid over points can have (see GridPixels.h).

#include "GridPixels.h"

#include <levelfuse/scan/SphereAngles.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace levelfuse::io {

namespace {

using openvdb::Vec3d;

/// Bins of azimuth for the arc the returns cover: a ten-thousandth of a turn each.
constexpr int kAzimuthBins = 1 << 16;

bool isReturn(const Vec3d& p) { return p != Vec3d(0.0); }

/// The arc of azimuths the returns cover, a turn less the widest gap between
/// them, overestimated by at most two bins (the gap is counted in whole empty bins).
double azimuthArcAtMost(const std::vector<Vec3d>& points) {
  std::vector<bool> filled(kAzimuthBins, false);
  for (const Vec3d& p : points) {
    if (!isReturn(p)) continue;
    const double turns = (std::atan2(p.y(), p.x()) + M_PI) / kTurn;
    filled[static_cast<std::size_t>(std::clamp(static_cast<int>(turns * kAzimuthBins), 0, kAzimuthBins - 1))] = true;
  }
  int widestGap = 0, gap = 0;
  for (int k = 0; k < 2 * kAzimuthBins; ++k) {  // twice round: a gap across azimuth -pi is counted whole
    gap = filled[static_cast<std::size_t>(k % kAzimuthBins)] ? 0 : gap + 1;
    widestGap = std::max(widestGap, std::min(gap, kAzimuthBins));
  }
  return kTurn * static_cast<double>(kAzimuthBins - widestGap) / kAzimuthBins;
}

/// The span of the returns' elevations.
double elevationSpan(const std::vector<Vec3d>& points) {
  double lowest = M_PI, highest = -M_PI;
  for (const Vec3d& p : points) {
    if (!isReturn(p)) continue;
    const double elevation = std::atan2(p.z(), std::hypot(p.x(), p.y()));
    lowest = std::min(lowest, elevation);
    highest = std::max(highest, elevation);
  }
  return std::max(0.0, highest - lowest);
}

}  // namespace

double gridPixelsAtMost(const std::vector<Vec3d>& points, const AngularSteps& steps) {
  const double columns = std::min(azimuthArcAtMost(points), kTurn) / steps.azimuth + 2.0;
  const double rows = elevationSpan(points) / steps.elevation + 2.0;
  return columns * rows;
}

}  // namespace levelfuse::io
