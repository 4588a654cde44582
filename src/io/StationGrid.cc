// levelfuse: a station's points on one grid, and the station as a range map.

#include "StationGridChecks.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/StationGrid.h>
#include <levelfuse/scan/SphericalScan.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
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

void requireGridOfTheStationsSize(const StationGrid& station, const AngularSteps& steps, const std::string& path,
                                  const std::string& scan) {
  const double points = static_cast<double>(station.columns) * static_cast<double>(station.rows);
  const double pixels = gridPixelsAtMost(station.points, steps);
  if (!(pixels <= kMaxPixelsPerPoint * points + kSpareGridPixels))
    throw InputError(path, scan + ": its returns span up to " +
                               rounded(pixels) + " pixels of its grid's steps (" + rounded(steps.azimuth) + " x " +
                               rounded(steps.elevation) + " rad), more than " + rounded(kMaxPixelsPerPoint) +
                               " per point of its " + std::to_string(station.columns) + " columns x " +
                               std::to_string(station.rows) + " rows: its points do not lie on one scanner's grid");
}

void requireReturnsOnTheirOwnPixels(const StationGrid& station, const RangeMap& map, const std::string& path,
                                    const std::string& scan) {
  if (2 * map.validCount() >= station.returns) return;
  const SphericalProjection& grid = map.sphericalProjection();
  throw InputError(path, scan + ": its " + std::to_string(station.returns) + " returns fill only " + std::to_string(map.validCount()) +
                             " pixels of its grid (" + std::to_string(map.width()) + " x " +
                             std::to_string(map.height()) + " of " + rounded(std::fabs(grid.azimuthStep)) + " x " +
                             rounded(std::fabs(grid.elevationStep)) +
                             " rad): its points do not lie on one scanner's grid");
}

RangeMap rangeMapFromStationGrid(const StationGrid& station, double sigma, const std::string& path,
                                 const std::string& scan, const std::string& name) {
  try {
    const AngularSteps steps = stepsOfGrid(station.points, station.columns, station.rows);
    requireGridOfTheStationsSize(station, steps, path, scan);
    RangeMap map = sphericalMapFromPoints(station.points, steps, station.scannerToWorld, sigma, name, station.colours);
    requireReturnsOnTheirOwnPixels(station, map, path, scan);
    return map;
  } catch (const std::invalid_argument& e) {  // the returns make no grid, or no map
    throw InputError(path, scan + ": " + e.what());
  }
}

}  // namespace levelfuse::io
