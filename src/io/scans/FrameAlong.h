// levelfuse: the frame a range grid is seen in, z along a line of sight
// (private to the readers).
#pragma once

#include <openvdb/math/Vec3.h>

#include <cmath>

namespace levelfuse::io {

/// A right-handed orthonormal frame whose z axis is a given direction, x and
/// y across it: y is z x (the world's x axis, or its y axis where z lies
/// within 26 degrees of x), x is y x z.
struct FrameAlong {
  openvdb::Vec3d x, y, z;

  /// `direction` must not be zero; its length does not matter.
  explicit FrameAlong(const openvdb::Vec3d& direction) : z(direction / direction.length()) {
    const openvdb::Vec3d helper = std::fabs(z.x()) < 0.9 ? openvdb::Vec3d(1, 0, 0) : openvdb::Vec3d(0, 1, 0);
    y = z.cross(helper).unit();
    x = y.cross(z);
  }

  /// A point's coordinates in the frame (whose origin is the world's).
  openvdb::Vec3d local(const openvdb::Vec3d& p) const { return openvdb::Vec3d(p.dot(x), p.dot(y), p.dot(z)); }
};

}  // namespace levelfuse::io
