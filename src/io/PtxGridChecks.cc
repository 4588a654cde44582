// levelfuse: a PTX scan's points on one grid.

#include "PtxGridChecks.h"

#include "PtxHeader.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/scan/SphericalScan.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

std::string rounded(double x) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", x);
  return text;
}

}  // namespace

double gridPixelsAtMost(const std::vector<Vec3d>& points, const AngularSteps& steps) {
  const double columns = std::min(azimuthArcAtMost(points), kTurn) / steps.azimuth + 2.0;
  const double rows = elevationSpan(points) / steps.elevation + 2.0;
  return columns * rows;
}

void requireGridOfTheScansSize(const PtxScan& scan, const AngularSteps& steps, const std::string& path) {
  const double points = static_cast<double>(scan.columns) * static_cast<double>(scan.rows);
  const double pixels = gridPixelsAtMost(scan.points, steps);
  if (!(pixels <= kMaxPixelsPerPoint * points + kSpareGridPixels))
    throw InputError(path, describePtxScan(scan.index, scan.firstLine, scan.lastLine) + ": its returns span up to " +
                               rounded(pixels) + " pixels of its grid's steps (" + rounded(steps.azimuth) + " x " +
                               rounded(steps.elevation) + " rad), more than " + rounded(kMaxPixelsPerPoint) +
                               " per point of its " + std::to_string(scan.columns) + " columns x " +
                               std::to_string(scan.rows) + " rows: its points do not lie on one scanner's grid");
}

void requireReturnsOnTheirOwnPixels(const PtxScan& scan, const RangeMap& map, const std::string& path) {
  if (2 * map.validCount() >= scan.returns) return;
  const SphericalProjection& grid = map.sphericalProjection();
  throw InputError(path, describePtxScan(scan.index, scan.firstLine, scan.lastLine) + ": its " +
                             std::to_string(scan.returns) + " returns fill only " + std::to_string(map.validCount()) +
                             " pixels of its grid (" + std::to_string(map.width()) + " x " +
                             std::to_string(map.height()) + " of " + rounded(std::fabs(grid.azimuthStep)) + " x " +
                             rounded(std::fabs(grid.elevationStep)) +
                             " rad): its points do not lie on one scanner's grid");
}

}  // namespace levelfuse::io
