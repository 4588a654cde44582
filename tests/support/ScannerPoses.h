// Angles in degrees and a scanner's pose, shared by the spherical scans' tests.
#pragma once

#include <openvdb/openvdb.h>

#include <cmath>

namespace levelfuse::test {

/// One degree, radians.
inline constexpr double kDegree = M_PI / 180.0;

/// A scanner turned 30 degrees about z and standing at (1, 2, 3).
inline openvdb::math::Mat4d scannerPose() {
  openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
  m.preRotate(openvdb::math::Z_AXIS, 30.0 * kDegree);
  m.setTranslation(openvdb::Vec3d(1.0, 2.0, 3.0));
  return m;
}

}  // namespace levelfuse::test
