// levelfuse: a scanner's point as the direction it was measured in (private
// to the binning of points into spherical range maps and to the estimate of
// their angular steps).
#pragma once

#include <levelfuse/scan/SphereAngles.h>

#include <openvdb/Types.h>

#include <cmath>
#include <optional>

namespace levelfuse::detail {

/// A point with a return: finite and not at the scanner.
inline bool hasReturn(const openvdb::Vec3d& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()) && p.lengthSqr() > 0.0;
}

inline double azimuthOf(const openvdb::Vec3d& p) { return std::atan2(p.y(), p.x()); }
inline double elevationOf(const openvdb::Vec3d& p) { return std::atan2(p.z(), std::hypot(p.x(), p.y())); }

/// Azimuth and elevation (radians) in the scanner's frame.
struct PointDirection {
  double azimuth, elevation;
};

/// The direction of a point that a spherical grid can hold: one with a
/// return, farther than kPoleMargin from either pole; none otherwise.
inline std::optional<PointDirection> binnableDirection(const openvdb::Vec3d& p) {
  if (!hasReturn(p)) return std::nullopt;
  const double elevation = elevationOf(p);
  if (std::fabs(elevation) > 0.5 * M_PI - kPoleMargin) return std::nullopt;
  return PointDirection{azimuthOf(p), elevation};
}

}  // namespace levelfuse::detail
