// levelfuse: the time-step rule of the explicit level-set update, shared by the
// sparse field and its dense-field reference.
#pragma once

namespace levelfuse {

/// The limits a time step keeps to; SparseFieldOptions and DenseFieldOptions
/// hold their values.
struct TimeStepLimits {
  double maxStepChange;       ///< largest change of a value in one step, in voxels (Eqs. 31-32)
  double curvatureStepLimit;  ///< stability of the explicit mean-curvature term: dt <= this * dx^2 / beta
  double stiffnessStepLimit;  ///< stability of a stiff force of stiffness k: dt k <= this
};

/// The time step for a grid of voxel size `dx` whose fastest point moves at
/// `maxSpeed` (world units per unit time), under a curvature term of weight
/// `curvatureWeight` and a force of stiffness `stiffness`, at most `maxDt`:
/// the fastest front moves at most maxStepChange voxels, and the curvature
/// and stiffness limits combine as rates do,
/// 1 / dt >= k / stiffnessStepLimit + beta / (curvatureStepLimit dx^2).
/// Zero where nothing finite and positive fits.
double stableTimeStep(const TimeStepLimits& limits, double dx, double maxSpeed, double curvatureWeight,
                      double stiffness, double maxDt);

}  // namespace levelfuse
