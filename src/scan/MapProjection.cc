// levelfuse: the projections of range maps: what the spherical grid's rows
// need out of line, and the kinds' names.

#include <levelfuse/scan/MapProjection.h>

#include <stdexcept>

namespace levelfuse {

void requireRowElevations(const std::vector<double>& rows, const std::string& who) {
  if (rows.size() < 2)
    throw std::invalid_argument(who + ": " + std::to_string(rows.size()) + " row elevation(s); uneven rows need two or more");
  for (std::size_t r = 0; r < rows.size(); ++r)
    if (!std::isfinite(rows[r]) || (r > 0 && !(rows[r] > rows[r - 1])))
      throw std::invalid_argument(who + ": the row elevations must be finite and strictly increasing (row " +
                                  std::to_string(r) + ")");
}

double elevationOfRow(const SphericalProjection& p, double v) {
  const std::vector<double>& rows = p.rowElevations;
  if (rows.empty()) return p.elevationStart + v * p.elevationStep;
  const std::size_t below = static_cast<std::size_t>(std::clamp(std::floor(v), 0.0, static_cast<double>(rows.size() - 2)));
  return rows[below] + (v - static_cast<double>(below)) * (rows[below + 1] - rows[below]);
}

double largestRowStep(const SphericalProjection& p) {
  const std::vector<double>& rows = p.rowElevations;
  double largest = std::fabs(p.elevationStep);
  for (std::size_t r = 1; r < rows.size(); ++r) largest = std::max(largest, rows[r] - rows[r - 1]);
  return largest;
}

openvdb::Vec3d sphericalDirection(const SphericalProjection& p, double u, double v) {
  const double azimuth = p.azimuthStart + u * p.azimuthStep;
  const double elevation = elevationOfRow(p, v);
  return openvdb::Vec3d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
}

const char* projectionName(MapProjection::Kind kind) {
  switch (kind) {
    case MapProjection::Kind::kOrthographic:
      return "orthographic";
    case MapProjection::Kind::kPinhole:
      return "pinhole";
    case MapProjection::Kind::kSpherical:
      return "spherical";
  }
  return "unknown";
}

}  // namespace levelfuse
