// levelfuse: how large a grid a PTX scan's returns make (private to the PTX
// reader): a scanner's own grid comes back about pixel for pixel, so a grid
// much larger than the scan's declared points means the points do not lie on
// the grid their steps say, and is refused before it is allocated.
#pragma once

#include <levelfuse/io/PtxScans.h>
#include <levelfuse/scan/SphericalScan.h>

#include <string>

namespace levelfuse::io {

/// A map may have at most this many pixels per point the scan declares (and
/// a few more: kSpareGridPixels).
inline constexpr double kMaxPixelsPerPoint = 4.0;
inline constexpr double kSpareGridPixels = 16.0;

/// At least as many pixels as binning the scan's returns with `steps` makes:
/// the arc of azimuths they cover and their span of elevations, in steps.
double gridPixelsAtMost(const PtxScan& scan, const AngularSteps& steps);

/// Throws InputError naming `path` and the scan if binning its returns with
/// `steps` could make more than kMaxPixelsPerPoint pixels per point.
void requireGridOfTheScansSize(const PtxScan& scan, const AngularSteps& steps, const std::string& path);

}  // namespace levelfuse::io
