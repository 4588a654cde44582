// levelfuse: checks that a station's points lie on one scanner's grid
// (private to the readers). A scanner's own grid comes back about pixel for
// pixel: a grid much larger than the scan's declared points is refused before
// it is allocated, and a map on which many returns share a pixel after it is
// made.
#pragma once

#include <levelfuse/io/StationGrid.h>
#include <levelfuse/scan/SphericalScan.h>

#include <string>
#include <vector>

namespace levelfuse::io {

/// A map may have at most this many pixels per point the scan declares (and
/// a few more: kSpareGridPixels).
inline constexpr double kMaxPixelsPerPoint = 4.0;
inline constexpr double kSpareGridPixels = 16.0;

/// At least as many pixels as binning the points (the origin where there was
/// no return) with `steps` makes: the arc of azimuths they cover and their
/// span of elevations, in steps.
double gridPixelsAtMost(const std::vector<openvdb::Vec3d>& points, const AngularSteps& steps);

/// Throws InputError naming `path` and `scan` if binning the station's
/// returns with `steps` could make more than kMaxPixelsPerPoint pixels per
/// point.
void requireGridOfTheStationsSize(const StationGrid& station, const AngularSteps& steps, const std::string& path,
                                  const std::string& scan);

/// Throws InputError naming `path` and `scan` if `map`, the station binned,
/// has readings for fewer than half its returns (the others shared a pixel).
void requireReturnsOnTheirOwnPixels(const StationGrid& station, const RangeMap& map, const std::string& path,
                                    const std::string& scan);

}  // namespace levelfuse::io
