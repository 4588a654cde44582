// levelfuse: the background value of a narrow-band level set.
#pragma once

#include <cmath>
#include <limits>

namespace levelfuse {

/// The background of a level set whose narrow band is `halfWidth` voxels wide:
/// the float nearest halfWidth * voxelSize that is not below it. OpenVDB's
/// checkLevelSet compares background / voxelSize with the half-width in double
/// precision, so the plainly rounded product (0.06f for 3 x 0.02) can fail it.
inline float levelSetBackground(double halfWidth, double voxelSize) {
  float background = static_cast<float>(halfWidth * voxelSize);
  while (static_cast<double>(background) / voxelSize < halfWidth)
    background = std::nextafter(background, std::numeric_limits<float>::max());
  return background;
}

}  // namespace levelfuse
