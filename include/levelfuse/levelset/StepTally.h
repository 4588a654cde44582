// levelfuse: what a step of the sparse field did, over a set of its leaves.
//
// A field split into slabs (SlabField.h) steps each slab on its own and adds
// the slabs' tallies. The sum must not depend on the order of addition, or the
// report of a step (and every decision taken on it, such as convergence)
// would depend on how the field was split. So the squared changes are summed
// in fixed point, where addition is exact, and every other field is a count or
// a maximum.
#pragma once

#include <levelfuse/levelset/StepResult.h>

#include <cstdint>

namespace levelfuse {

struct StepTally {
  /// Fixed point of the squared changes: units of 2^-kFractionBits voxel^2.
  /// A leaf's 512 points change by less than 1/2 voxel each, so a leaf adds
  /// less than 2^63 units.
  static constexpr int kFractionBits = 56;

  double dt = 0.0;
  double maxSpeed = 0.0;                ///< largest |d psi/dt| (world units per time)
  double maxChange = 0.0;               ///< largest change (world units)
  std::uint64_t squaredChangeHigh = 0;  ///< the sum of squared changes, 128-bit fixed point
  std::uint64_t squaredChangeLow = 0;
  std::uint64_t points = 0;             ///< active points changed
  std::uint64_t pointsAtRest = 0;       ///< of those, points the speed left at rest
  std::uint64_t activeSetVoxels = 0;    ///< |L0| after the step
  std::uint64_t movedOut = 0;
  std::uint64_t movedIn = 0;
  std::uint64_t conflicts = 0;

  /// Adds one leaf's sum of squared changes, in voxels^2 (truncated to the fixed point).
  void addSquaredChanges(double voxelsSquared);
  /// Adds the tally of a disjoint set of leaves of the same step.
  StepTally& operator+=(const StepTally& other);
  /// The step's report; `dx` is the voxel size.
  StepResult result(double dx) const;
};

}  // namespace levelfuse
