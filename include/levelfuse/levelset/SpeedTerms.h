// levelfuse: the speed terms that move a level set.
//
// The level-set engines (SparseField, DenseField) call a *speed* once per
// updated grid point with the point's local geometry, and the speed returns
// d(psi)/dt there. In OpenVDB's convention (psi negative inside) a surface
// moving outward with normal speed F obeys d psi/dt = -F |grad psi|, and the
// surface-area prior of weight beta adds beta kappa |grad psi| (Eq. 27).
//
// A speed is any type with
//   float operator()(const ActivePoint&) const;   // d psi / dt, world units per unit time
//   double curvatureWeight() const;               // beta, for the time-step limit (0 if none)
// and optionally
//   double stiffness() const;                     // see speedStiffness() below
//   bool atRestIn(const openvdb::CoordBBox&, const openvdb::math::Transform&) const;  // see speedAtRestIn()
//   Local local() const;                          // see localSpeed() below
// Engines are templates over the speed, so the per-point call inlines.
#pragma once

#include <levelfuse/levelset/Stencil.h>

#include <openvdb/math/BBox.h>
#include <openvdb/math/Coord.h>
#include <openvdb/math/Transform.h>

#include <functional>
#include <type_traits>
#include <utility>

namespace levelfuse {

namespace detail {
template <typename T, typename = void>
struct HasStiffness : std::false_type {};
template <typename T>
struct HasStiffness<T, std::void_t<decltype(std::declval<const T&>().stiffness())>> : std::true_type {};
template <typename T, typename = void>
struct HasAtRest : std::false_type {};
template <typename T>
struct HasAtRest<T, std::void_t<decltype(std::declval<const T&>().atRestIn(
                        std::declval<const openvdb::CoordBBox&>(), std::declval<const openvdb::math::Transform&>()))>>
    : std::true_type {};
template <typename T, typename = void>
struct HasLocal : std::false_type {};
template <typename T>
struct HasLocal<T, std::void_t<decltype(std::declval<const T&>().local())>> : std::true_type {};
template <typename T, typename = void>
struct HasVanishes : std::false_type {};
template <typename T>
struct HasVanishes<T, std::void_t<decltype(std::declval<const T&>().vanishesIn(std::declval<const openvdb::BBoxd&>()))>>
    : std::true_type {};
}  // namespace detail

/// How fast a speed (or force) pulls a displaced surface back, per unit time:
/// an upper bound of -d(rate)/d(psi) of its part other than the curvature
/// term, e.g. 1 for a force that is the distance to a target surface. An
/// explicit step must keep dt * stiffness well below 1; 0 for types without a
/// stiffness() member.
template <typename T>
double speedStiffness(const T& speed) {
  if constexpr (detail::HasStiffness<T>::value) return speed.stiffness();
  else return 0.0;
}

/// Whether a speed is 0 at every grid point of the index box `voxels` (of a
/// grid with `transform`), whatever the values around the points: the engines
/// then leave such points as they are without gathering their stencils. False
/// for types without an atRestIn() member, at no cost.
template <typename T>
bool speedAtRestIn(const T& speed, const openvdb::CoordBBox& voxels, const openvdb::math::Transform& transform) {
  if constexpr (detail::HasAtRest<T>::value) return speed.atRestIn(voxels, transform);
  else return false;
}

/// The speed as one task of an engine asks it, point after point of one leaf
/// node: `speed.local()` where the speed offers one (a copy that keeps state
/// of its own, such as tree accessors that cache the nodes the leaf's points
/// share), the speed itself otherwise. A local speed gives the same rates as
/// the speed, bit for bit.
template <typename T>
decltype(auto) localSpeed(const T& speed) {
  if constexpr (detail::HasLocal<T>::value) return speed.local();
  else return speed;  // a reference: no copy
}

/// Whether a force is 0 at every point of the world box `box` and for every
/// normal; false for types without a vanishesIn() member.
template <typename T>
bool forceVanishesIn(const T& force, const openvdb::BBoxd& box) {
  if constexpr (detail::HasVanishes<T>::value) return force.vanishesIn(box);
  else return false;
}

/// The world box in which the speed of a point of the index box `voxels`
/// samples its force: x^ lies within a voxel of its grid point along each
/// axis (subcellOffset).
inline openvdb::BBoxd forceSamplingBox(const openvdb::CoordBBox& voxels, const openvdb::math::Transform& transform) {
  return transform.indexToWorld(openvdb::CoordBBox(voxels.min().offsetBy(-1), voxels.max().offsetBy(1)));
}

/// What a speed sees of one grid point being updated.
struct ActivePoint {
  const Stencil& stencil;                       ///< values around the point (world units)
  openvdb::Coord ijk;                           ///< index-space position
  const openvdb::math::Transform& transform;   ///< index to world
  /// The transform's map, found once by the caller: Transform::baseMap()
  /// hands out a shared pointer, whose count two threads would contend for
  /// at every point.
  const openvdb::math::MapBase& map;

  /// World-space position of the grid point.
  openvdb::Vec3d worldPosition() const { return transform.indexToWorld(ijk); }

  /// World-space position x^ of the nearby zero crossing (Eqs. 34-36).
  openvdb::Vec3d subcellPosition() const {
    const openvdb::Vec3f offset = subcellOffset(stencil) / stencil.h;  // in voxels
    return transform.indexToWorld(openvdb::Vec3d(ijk.asVec3d()) + openvdb::Vec3d(offset));
  }

  /// Outward unit normal in world space (central differences); zero where the
  /// gradient vanishes.
  openvdb::Vec3d normal() const {
    openvdb::Vec3d n = map.applyJacobian(openvdb::Vec3d(centralGradient(stencil)));
    const double length = n.length();
    return length > 0.0 ? n / length : openvdb::Vec3d(0.0);
  }
};

/// Mean-curvature flow, d psi/dt = beta kappa |grad psi| (Eqs. 19, 26): the
/// Euler-Lagrange term of the surface-area prior. A sphere of radius R shrinks
/// as R(t)^2 = R0^2 - 4 beta t.
struct MeanCurvatureFlow {
  double beta = 1.0;

  float operator()(const ActivePoint& p) const {
    return static_cast<float>(beta) * meanCurvatureTerm(p.stencil);  // Eq. 26
  }
  double curvatureWeight() const { return beta; }
};

/// d psi/dt of a surface pushed outward at speed `f` with the surface-area
/// prior of weight `beta`: -f |grad psi| + beta kappa |grad psi| (Eq. 27).
inline float forceRate(const Stencil& stencil, float f, double beta) {
  float rate = -f * upwindGradientMagnitude(stencil, f);                          // Eq. 30
  if (beta != 0.0) rate += static_cast<float>(beta) * meanCurvatureTerm(stencil);  // Eq. 26
  return rate;
}

/// Where a ForceSpeed samples its force.
enum class ForceSampling {
  kSubcell,    ///< at the zero crossing x^ near the grid point (Eqs. 34-36)
  kGridPoint,  ///< at the grid point itself (the classic scheme; aliases, Fig. 7-8)
};

/// A force field moving the surface along its normal, plus the surface-area prior:
///   d psi/dt = -F(x, N) |grad psi| + beta kappa |grad psi|   (Eqs. 27, 30, 37)
/// F is the outward normal speed (positive: the surface grows), evaluated at
/// the subcell position x^ (or the grid point) and the outward normal N.
/// `Force` is callable as `double(const openvdb::Vec3d& x, const openvdb::Vec3d& n)`.
template <typename Force>
struct ForceSpeed {
  Force force;
  double beta = 0.0;
  ForceSampling sampling = ForceSampling::kSubcell;

  float operator()(const ActivePoint& p) const {
    const openvdb::Vec3d x =
        sampling == ForceSampling::kSubcell ? p.subcellPosition() : p.worldPosition();
    return forceRate(p.stencil, static_cast<float>(force(x, p.normal())), beta);
  }
  double curvatureWeight() const { return beta; }
  double stiffness() const { return speedStiffness(force); }
  /// Without the prior, at rest where the force vanishes.
  bool atRestIn(const openvdb::CoordBBox& voxels, const openvdb::math::Transform& transform) const {
    return beta == 0.0 && forceVanishesIn(force, forceSamplingBox(voxels, transform));
  }
  /// For one task (localSpeed): the force's own local copy, where it has one.
  template <typename F = Force, typename = std::enable_if_t<detail::HasLocal<F>::value>>
  auto local() const {
    using Local = decltype(force.local());
    return ForceSpeed<Local>{force.local(), beta, sampling};
  }
};

/// A constant outward normal speed (negative: the surface shrinks).
struct ConstantForce {
  double speed = 1.0;
  double operator()(const openvdb::Vec3d&, const openvdb::Vec3d&) const { return speed; }
};

/// Any force given at run time: outward speed at world position x with outward normal n.
using ExternalForce = std::function<double(const openvdb::Vec3d& x, const openvdb::Vec3d& n)>;

/// Surface moving along its normal at a constant speed, R(t) = R0 + speed t.
using ConstantSpeed = ForceSpeed<ConstantForce>;
/// An external force field plus the prior; the seam where the MAP data term plugs in.
using ExternalForceSpeed = ForceSpeed<ExternalForce>;

}  // namespace levelfuse
