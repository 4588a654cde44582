// levelfuse: the angles of the sphere around a spherical scanner that its
// range maps and the directions of its points share: a whole turn of azimuth,
// and the margin near the poles where a point has no azimuth a grid can hold.
#pragma once

#include <cmath>

namespace levelfuse {

/// A whole turn, radians.
inline constexpr double kTurn = 2.0 * M_PI;

/// Points closer to a pole than this (radians, 0.1 degree) have no azimuth a
/// grid can hold: binning leaves them out.
inline constexpr double kPoleMargin = 0.1 * M_PI / 180.0;

}  // namespace levelfuse
