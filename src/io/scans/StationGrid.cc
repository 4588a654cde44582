// levelfuse: a station's points on one grid, and the station as a range map.

#include "GridPixels.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/scans/StationGrid.h>
#include <levelfuse/scan/SphericalScan.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace levelfuse::io {

namespace {

std::string rounded(double x) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", x);
  return text;
}

/// Throws InputError naming `path` and `scan` if binning the station's
/// returns with `steps` could make more than kMaxPixelsPerPoint pixels per
/// point.
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

/// Throws InputError naming `path` and `scan` if `map`, the station binned,
/// has readings for fewer than half its returns (the others shared a pixel).
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

}  // namespace

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
