// levelfuse: the speed of the MAP evolution (paper section 3, Eqs. 27, 37).
//
//   d psi/dt = -F(x^, N) |grad psi|_upwind + beta kappa |grad psi|
//
// with the data force F the facing-checked data term g~ (Eq. 37) sampled at
// the subcell position x^ (Eqs. 34-36) and turned into an outward normal speed
// in world units,
//
//   F = (g~ / W~) min(1, N~),
//
// W~ the weight of the facing terms (sum c w gamma) and N~ the number of
// readings among them (sum w). Where one reading or more reaches x^, F is the
// readings' weighted mean distance along their lines of sight, so the prior's
// weight means the same whatever the number of readings, their depth and their
// noise, and an explicit step of up to one time unit relaxes the data term
// without overshooting; where less than one reading's window reaches, F fades
// with N~ (weak data: the prior governs there, as the paper intends). What one
// reading weighs is taken where the readings are: a depth camera's readings
// weigh c gamma ~ 1 / (z^2 sigma(z)^2), a thousand times less at 3 m than at
// 1 m, and one weight for all of them made the far half of a room's data
// term too weak to hold against the prior (docs/RECONSTRUCTION.md).
#pragma once

#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>
#include <levelfuse/scan/DataTermGrids.h>
#include <levelfuse/scan/ForceField.h>

#include <algorithm>
#include <limits>
#include <type_traits>
#include <utility>

namespace levelfuse {

/// The data force of the MAP evolution: outward normal speed at x for a surface
/// with outward normal n (world units per unit time), from a data term that
/// answers facingTerms(x, n) (Eq. 37): DataTermGrids, sampled from grids, or
/// ForceField, evaluated per range map.
template <typename Field>
struct DataForce {
  const Field* field = nullptr;
  /// The largest |F| returned (world units per unit time): F is clamped to
  /// [-limit, limit], which keeps every zero of F where it was.
  double limit = std::numeric_limits<double>::infinity();

  double operator()(const openvdb::Vec3d& x, const openvdb::Vec3d& n) const {
    return forceOf(field->facingTerms(x, n), limit);  // Eq. 37
  }
  /// F from the facing terms at x, clamped to [-limit, limit].
  static double forceOf(const DataTerms& t, double limit) {
    if (!(t.weight > 0.0)) return 0.0;
    return std::clamp(t.g / t.weight * std::min(1.0, t.readings), -limit, limit);
  }
  /// The force for one task (localSpeed): the same, through the field's own
  /// sampler where it has one (DataTermGrids::Sampler).
  template <typename F = Field, typename = std::enable_if_t<detail::HasSampler<F>::value>>
  auto local() const {
    struct Sampled {
      double limit;
      mutable decltype(std::declval<const F&>().sampler()) sampler;
      double operator()(const openvdb::Vec3d& x, const openvdb::Vec3d& n) const {
        return forceOf(sampler.facingTerms(x, n), limit);  // Eq. 37
      }
    };
    return Sampled{limit, field->sampler()};
  }
  /// At most 1 per unit time: F is at most a weighted mean of distances along
  /// lines of sight, which change by at most the distance the surface moves.
  double stiffness() const { return 1.0; }
  /// F is 0 where no reading's window reaches (for a data term that can tell).
  bool vanishesIn(const openvdb::BBoxd& box) const { return !mayHaveTermsIn(*field, box); }
};

/// The data force's limit when the prior is off (DataForce::limit, set by the
/// Reconstructor; world units per unit time, on a grid of voxel size
/// `voxelSize` with the window's width `epsilon` as derived from the readings'
/// noise, before it is widened to a voxel).
///
/// Half a voxel: a step moves no value by more than
/// SparseFieldOptions::maxStepChange (0.45 voxel), so the time step is 0.45
/// voxel over the largest rate, and on depth frames a few points whose readings
/// lie voxels away would hold it at 0.1 to 0.2: every other point would relax
/// its distance by 10 to 20% a step. Clamped to half a voxel, the step comes
/// close to the stiffness limit (0.5; 0.4 measured), every point relaxes by
/// almost half, and the far points still move their 0.45 voxel a step.
///
/// Not below epsilon: readings scatter about their surface by about epsilon, and
/// a clamp below it cuts the force of ordinary readings, not of a few far ones,
/// and turns the relaxation into a motion at constant speed (the torus with
/// noise of 9 voxels and no prior, clamped to half a voxel, ended 0.184 sigma
/// from the truth after 120 iterations, against 0.160 after 88).
///
/// Without the prior the zeros of F are the evolution's fixed points and the
/// clamp keeps them; with it, F balances the prior's beta kappa, which can
/// exceed half a voxel per unit time at a corner, so the prior's fixed points
/// would move, and F is left unclamped.
inline double forceLimitWithoutPrior(double voxelSize, double epsilon) { return std::max(0.5 * voxelSize, epsilon); }

/// The MAP evolution's speed: the data force at x^ plus the surface-area prior
/// (ForceSpeed::beta, the weight of kappa |grad psi| in world units squared per
/// unit time). SparseField::step is instantiated for both by the library.
template <typename Field>
using DataSpeed = ForceSpeed<DataForce<Field>>;

}  // namespace levelfuse
