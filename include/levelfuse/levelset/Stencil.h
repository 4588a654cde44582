// levelfuse: finite differences on the 19-point stencil of an active point.
//
// The sparse field and the dense field share these functions, so the two
// evolve the level set with exactly the same numerical scheme. Values are in
// world units, `h` is the voxel size. Equation numbers refer to Whitaker (1998).
#pragma once

#include <openvdb/Types.h>

#include <algorithm>
#include <cmath>

namespace levelfuse {

/// The centre voxel, its 6 face neighbours and its 12 edge neighbours
/// (the 3x3x3 box without its corners): all that first and second
/// derivatives on the 3x3x3 kernel of the paper need.
struct Stencil {
  enum Index : int {
    kCentre = 0,
    kXm, kXp, kYm, kYp, kZm, kZp,           // face neighbours
    kXmYm, kXmYp, kXpYm, kXpYp,             // edges in the xy plane
    kXmZm, kXmZp, kXpZm, kXpZp,             // edges in the xz plane
    kYmZm, kYmZp, kYpZm, kYpZp,             // edges in the yz plane
    kSize
  };
  /// Offsets of the stencil points, in the order of Index.
  static constexpr int kOffset[kSize][3] = {
      {0, 0, 0},
      {-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1},
      {-1, -1, 0}, {-1, 1, 0}, {1, -1, 0}, {1, 1, 0},
      {-1, 0, -1}, {-1, 0, 1}, {1, 0, -1}, {1, 0, 1},
      {0, -1, -1}, {0, -1, 1}, {0, 1, -1}, {0, 1, 1}};

  float u[kSize];
  float h = 1.0f;  ///< voxel size (world units)

  float centre() const { return u[kCentre]; }

  // One-sided differences, Eqs. 28-29.
  float backward(int axis) const { return (u[kCentre] - u[kXm + 2 * axis]) / h; }
  float forward(int axis) const { return (u[kXp + 2 * axis] - u[kCentre]) / h; }
  float central(int axis) const { return 0.5f * (u[kXp + 2 * axis] - u[kXm + 2 * axis]) / h; }
  float second(int axis) const {
    return (u[kXp + 2 * axis] - 2.0f * u[kCentre] + u[kXm + 2 * axis]) / (h * h);
  }
};

/// |grad u| by the up-wind scheme of Osher and Sethian (Eq. 30) for
/// d(psi)/dt = -F |grad psi|, where F is the outward normal speed: the
/// differences are taken from the side the front comes from.
inline float upwindGradientMagnitude(const Stencil& s, float outwardSpeed) {
  float sum = 0.0f;
  if (outwardSpeed > 0.0f) {
    for (int a = 0; a < 3; ++a) {
      const float bm = std::max(s.backward(a), 0.0f);
      const float fp = std::min(s.forward(a), 0.0f);
      sum += bm * bm + fp * fp;
    }
  } else {
    for (int a = 0; a < 3; ++a) {
      const float bm = std::min(s.backward(a), 0.0f);
      const float fp = std::max(s.forward(a), 0.0f);
      sum += bm * bm + fp * fp;
    }
  }
  return std::sqrt(sum);
}

/// Central-difference gradient.
inline openvdb::Vec3f centralGradient(const Stencil& s) {
  return openvdb::Vec3f(s.central(0), s.central(1), s.central(2));
}

/// kappa |grad u|, the mean-curvature term of Eq. 26, with kappa the sum of the
/// principal curvatures (2/R on a sphere of radius R; positive where the surface
/// is convex in OpenVDB's negative-inside convention). Central differences on
/// the 3x3x3 kernel.
inline float meanCurvatureTerm(const Stencil& s) {
  const float ux = s.central(0), uy = s.central(1), uz = s.central(2);
  const float uxx = s.second(0), uyy = s.second(1), uzz = s.second(2);
  const float q = 0.25f / (s.h * s.h);
  const float uxy = q * (s.u[Stencil::kXpYp] - s.u[Stencil::kXpYm] - s.u[Stencil::kXmYp] + s.u[Stencil::kXmYm]);
  const float uxz = q * (s.u[Stencil::kXpZp] - s.u[Stencil::kXpZm] - s.u[Stencil::kXmZp] + s.u[Stencil::kXmZm]);
  const float uyz = q * (s.u[Stencil::kYpZp] - s.u[Stencil::kYpZm] - s.u[Stencil::kYmZp] + s.u[Stencil::kYmZm]);
  const float ux2 = ux * ux, uy2 = uy * uy, uz2 = uz * uz;
  const float gradSq = ux2 + uy2 + uz2;
  // Where the gradient vanishes (an isolated extremum: a component shrunk to a
  // voxel) the level sets are tiny closed surfaces; kappa |grad u| tends to
  // (2/3) of the Laplacian there for an isotropic extremum, so it collapses.
  if (!(gradSq > 1.0e-12f)) return (2.0f / 3.0f) * (uxx + uyy + uzz);
  const float numerator = (uy2 + uz2) * uxx + (ux2 + uz2) * uyy + (ux2 + uy2) * uzz -
                          2.0f * (ux * uy * uxy + uy * uz * uyz + ux * uz * uxz);
  return numerator / gradSq;
}

/// MaxAbs of Eq. 35: the steeper of two one-sided differences, their mean on a tie.
inline float maxAbs(float a, float b) {
  const float fa = std::fabs(a), fb = std::fabs(b);
  if (fa > fb) return a;
  if (fa < fb) return b;
  return 0.5f * (a + b);
}

/// The gradient used to locate the nearest zero crossing, Eq. 36.
inline openvdb::Vec3f maxAbsGradient(const Stencil& s) {
  return openvdb::Vec3f(maxAbs(s.backward(0), s.forward(0)), maxAbs(s.backward(1), s.forward(1)),
                        maxAbs(s.backward(2), s.forward(2)));
}

/// Offset (world units, index axes) from the grid point to the nearest point of
/// the zero level set, x^ - x = -u grad u / (grad u . grad u) (Eq. 34), with
/// grad u from Eq. 36. A vanishing gradient is the special case of Eq. 34: the
/// grid point itself is used. The offset is limited to one voxel per axis, the
/// farthest an active point's zero crossing can be.
inline openvdb::Vec3f subcellOffset(const Stencil& s) {
  const openvdb::Vec3f g = maxAbsGradient(s);
  const float gg = g.lengthSqr();
  if (!(gg > 1.0e-12f)) return openvdb::Vec3f(0.0f);
  openvdb::Vec3f d = g * (-s.centre() / gg);
  for (int a = 0; a < 3; ++a) d[a] = std::clamp(d[a], -s.h, s.h);
  return d;
}

}  // namespace levelfuse
