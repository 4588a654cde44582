// levelfuse: the pixels a spherical grid over a scan's points can have
// (private to the readers). A scanner's own grid comes back about pixel for
// pixel: a grid much larger than the scan's points is refused before it is
// allocated.
#pragma once

#include <levelfuse/scan/SphericalScan.h>

#include <openvdb/Types.h>

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

}  // namespace levelfuse::io
