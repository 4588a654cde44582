// levelfuse: the eight voxels around a point and their trilinear weights
// (private to the samplers of the data term's and the colour's grids).
#pragma once

#include <openvdb/math/Coord.h>
#include <openvdb/math/Vec3.h>

namespace levelfuse::detail {

struct TrilinearCorners {
  openvdb::Coord ijk[8];  ///< corner k is lo + (k & 1, (k >> 1) & 1, k >> 2)
  double t[8];            ///< their weights, summing to 1
};

/// The corners of the cell holding `index` (a point in index space) and the
/// trilinear weight of each at it.
inline TrilinearCorners trilinearCorners(const openvdb::Vec3d& index) {
  TrilinearCorners c;
  const openvdb::Coord lo = openvdb::Coord::floor(index);
  const openvdb::Vec3d f = index - lo.asVec3d();
  for (int k = 0; k < 8; ++k) {
    const int dx = k & 1, dy = (k >> 1) & 1, dz = k >> 2;
    c.ijk[k] = lo.offsetBy(dx, dy, dz);
    c.t[k] = (dx ? f.x() : 1.0 - f.x()) * (dy ? f.y() : 1.0 - f.y()) * (dz ? f.z() : 1.0 - f.z());
  }
  return c;
}

}  // namespace levelfuse::detail
