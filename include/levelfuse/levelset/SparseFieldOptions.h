// levelfuse: the settings of the sparse-field engine (SparseField.h), which
// its slabs (SlabField.h) and its internal state share.
#pragma once

#include <cstddef>

namespace levelfuse {

/// Settings of the sparse-field engine.
struct SparseFieldOptions {
  /// N, the number of layers on each side of the active set. The 3x3x3 kernel
  /// of the curvature term needs N >= 2 (section 5); at most 3.
  int layers = 2;
  /// Largest change of an active value in one step, in voxels. Must stay below
  /// 1/2 so that no point skips a layer (section 5).
  double maxStepChange = 0.45;
  /// Stability limit of the explicit mean-curvature term: dt <= this * dx^2 / beta.
  /// At the active points the term acts as diffusion within the surface, whose
  /// explicit limit is 1/4 (2D); measured on noisy spheres, 0.25 damps noise as
  /// fast as 1/6 while 0.3 lets it grow for a while.
  double curvatureStepLimit = 0.25;
  /// Limit for speeds with a stiffness k (see speedStiffness): dt k <= this,
  /// so that a displaced surface relaxes without overshooting. With a
  /// curvature term as well, the two limits combine as rates do:
  /// 1 / dt >= k / stiffnessStepLimit + beta / (curvatureStepLimit dx^2).
  double stiffnessStepLimit = 0.5;
  /// Leaf nodes per parallel task; 0 runs every phase serially.
  std::size_t grainSize = 4;
  /// A step keeps the layers of a leaf whose 3 x 3 x 3 neighbourhood of
  /// leaves it left unchanged, which the layer rule would rebuild as they
  /// are (the same values); false rebuilds every leaf's.
  bool keepSettledLayers = true;
};

}  // namespace levelfuse
