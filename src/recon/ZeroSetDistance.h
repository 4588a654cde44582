// levelfuse: distances from points to a level set's zero set, for points
// beyond its narrow band.
#pragma once

#include <openvdb/openvdb.h>

#include <vector>

namespace levelfuse::detail {

/// The distance (world units) from each of `points` to the nearest point of
/// `levelSet`'s zero set, as meshed by meshFromLevelSet. The zero set is
/// meshed only in cubes around the points, `firstReach` voxels each way at
/// first and doubled for the points whose nearest surface lies beyond their
/// cube, so that its memory grows with the points, not with the surface.
/// When the cubes would hold more voxels than the band, or a cube would span
/// it, the remaining points are measured once to the nearest vertex of the
/// whole zero set's mesh (ClosestSurfacePoint). A point with no zero set
/// anywhere gets infinity.
std::vector<double> distancesToZeroSet(const openvdb::FloatGrid& levelSet, const std::vector<openvdb::Vec3d>& points,
                                       int firstReach = 16);

}  // namespace levelfuse::detail
