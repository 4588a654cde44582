// levelfuse: what one step of a level-set field did (SparseField::step,
// DenseField::step; StepTally::result for a field stepped slab by slab).
#pragma once

#include <cstddef>

namespace levelfuse {

/// What one step did.
struct StepResult {
  double dt = 0.0;                 ///< time advanced
  double maxSpeed = 0.0;           ///< largest |d psi/dt| over the active set (world units per time)
  double maxChange = 0.0;          ///< largest change of an active value (world units)
  double rmsChange = 0.0;          ///< rms change of the active values (world units)
  /// rms change of the active values the speed did not leave at rest
  /// (speedAtRestIn; world units): the motion of the surface the speed acts on.
  double rmsChangeNotAtRest = 0.0;
  std::size_t pointsAtRest = 0;    ///< active points the speed left at rest
  std::size_t activeSetVoxels = 0;    ///< |L0| after the step
  std::size_t movedOut = 0;        ///< points that left L0 outward (into L+1)
  std::size_t movedIn = 0;         ///< points that left L0 inward (into L-1)
  std::size_t conflicts = 0;       ///< adjacent points that tried to leave L0 on opposite sides
};

}  // namespace levelfuse
