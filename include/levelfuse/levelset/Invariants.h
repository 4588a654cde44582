// levelfuse: the sparse field's invariants (section 5 and the Appendix), checked.
#pragma once

#include <levelfuse/levelset/SparseField.h>

#include <cstddef>
#include <string>

namespace levelfuse {

/// What checkInvariants found. The first three counts must be zero for a
/// consistent field; inefficient active points are allowed at singularities.
struct InvariantReport {
  /// 6-adjacent voxel pairs of opposite sign with neither in L0 (the active
  /// set must separate inside from outside, Appendix).
  std::size_t separationViolations = 0;
  /// Layer voxels whose values leave their range: [-1/2, 1/2] voxel in L0,
  /// [i - 1/2, i + 1/2] voxel (signed) in L+-i; background elsewhere.
  std::size_t rangeViolations = 0;
  /// Layer voxels out of place: L+-i without a neighbour in L+-(i-1), layers
  /// that disagree with the band, neighbours more than one layer apart, leaves
  /// without layers.
  std::size_t structureViolations = 0;
  /// Active points with no neighbour of opposite sign (an "inefficient" active set).
  std::size_t inefficientActive = 0;
  std::size_t activeSetVoxels = 0;
  std::string firstViolation;  ///< a readable description of the first problem found

  bool ok() const { return separationViolations == 0 && rangeViolations == 0 && structureViolations == 0; }
};

/// Checks every voxel of the layers and their neighbours (serial; for tests).
InvariantReport checkInvariants(const SparseField& field);

}  // namespace levelfuse
