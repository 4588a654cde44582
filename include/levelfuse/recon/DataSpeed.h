// levelfuse: the speed of the MAP evolution (paper section 3, Eqs. 27, 37).
//
//   d psi/dt = -F(x^, N) |grad psi|_upwind + beta kappa |grad psi|
//
// with the data force F the facing-checked data term g~ (Eq. 37) sampled at
// the subcell position x^ (Eqs. 34-36) and turned into an outward normal speed
// in world units: F = g~ / max(W~, W1), W~ the weight of the facing terms and
// W1 a single typical reading's weight c gamma. Where a single reading or less
// supports the surface, F is the MAP force itself, scaled to length units
// (weak data: the prior dominates there, as the paper intends); where several
// readings overlap, F is their weighted mean distance, so the prior's weight
// means the same whatever the number of overlapping scans, and an explicit
// step of up to one time unit relaxes the data term without overshooting.
#pragma once

#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>
#include <levelfuse/scan/DataTermGrids.h>
#include <levelfuse/scan/ForceField.h>

#include <algorithm>

namespace levelfuse {

/// The data force of the MAP evolution: outward normal speed at x for a surface
/// with outward normal n (world units per unit time), from a data term that
/// answers facingTerms(x, n) (Eq. 37): DataTermGrids, sampled from grids, or
/// ForceField, evaluated per range map.
template <typename Field>
struct DataForce {
  const Field* field = nullptr;
  double unitWeight = 1.0;  ///< W1: a single typical reading's weight (Field::typicalWeight)

  double operator()(const openvdb::Vec3d& x, const openvdb::Vec3d& n) const {
    const DataTerms t = field->facingTerms(x, n);  // Eq. 37
    return t.g / std::max(t.weight, unitWeight);
  }
  /// At most 1 per unit time: F is at most a weighted mean of distances along
  /// lines of sight, which change by at most the distance the surface moves.
  double stiffness() const { return 1.0; }
};

/// The MAP evolution's speed: the data force at x^ plus the surface-area prior
/// (ForceSpeed::beta, the weight of kappa |grad psi| in world units squared per
/// unit time). SparseField::step is instantiated for both by the library.
template <typename Field>
using DataSpeed = ForceSpeed<DataForce<Field>>;

}  // namespace levelfuse
