// levelfuse: the direction bins of lines of sight.

#include <levelfuse/scan/SightBins.h>

#include <cmath>

namespace levelfuse {

namespace {

std::array<openvdb::Vec3d, kSightBins> icosahedronVertices() {
  const double phi = 0.5 * (1.0 + std::sqrt(5.0));
  std::array<openvdb::Vec3d, kSightBins> v;
  int n = 0;
  for (int s1 = -1; s1 <= 1; s1 += 2)
    for (int s2 = -1; s2 <= 1; s2 += 2) {
      v[n++] = openvdb::Vec3d(0.0, s1, s2 * phi);
      v[n++] = openvdb::Vec3d(s1, s2 * phi, 0.0);
      v[n++] = openvdb::Vec3d(s2 * phi, 0.0, s1);
    }
  for (openvdb::Vec3d& d : v) d.normalize();
  return v;
}

}  // namespace

const std::array<openvdb::Vec3d, kSightBins>& sightBinCentres() {
  static const std::array<openvdb::Vec3d, kSightBins> centres = icosahedronVertices();
  return centres;
}

int sightBin(const openvdb::Vec3d& direction) {
  const std::array<openvdb::Vec3d, kSightBins>& centres = sightBinCentres();
  int best = 0;
  double bestDot = direction.dot(centres[0]);
  for (int b = 1; b < kSightBins; ++b) {
    const double d = direction.dot(centres[static_cast<std::size_t>(b)]);
    if (d > bestDot) {
      bestDot = d;
      best = b;
    }
  }
  return best;
}

int sightBinOfRoundCone(const openvdb::Vec3d& axis, double sinHalfAngle) {
  constexpr double kClearly = 1e-9;  // in dot products of unit vectors: far above their rounding
  if (!(sinHalfAngle >= 0.0 && sinHalfAngle < 1.0)) return -1;
  const std::array<openvdb::Vec3d, kSightBins>& centres = sightBinCentres();
  const int bin = sightBin(axis);
  const double own = axis.dot(centres[static_cast<std::size_t>(bin)]);
  const double cosHalfAngle = std::sqrt(1.0 - sinHalfAngle * sinHalfAngle);
  // A unit d within the cone, at angle t <= a from the axis, and w = c_bin - c_b:
  // d . w >= cos(t) (axis . w) - sin(t) |w| >= cos(a) (axis . w) - sin(a) |w| where axis . w > 0.
  for (int b = 0; b < kSightBins; ++b) {
    if (b == bin) continue;
    const double ahead = own - axis.dot(centres[static_cast<std::size_t>(b)]);
    const double apart = (centres[static_cast<std::size_t>(bin)] - centres[static_cast<std::size_t>(b)]).length();
    if (!(cosHalfAngle * ahead - sinHalfAngle * apart > kClearly)) return -1;
  }
  return bin;
}

}  // namespace levelfuse
