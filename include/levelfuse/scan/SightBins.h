// levelfuse: lines of sight sorted into a few direction bins, so that the
// facing check of Eq. 37 can be made on accumulated grids.
//
// The bins are the Voronoi cells, on the unit sphere, of the 12 vertices of a
// regular icosahedron: every direction lies within 37.4 degrees of its bin's
// centre, and two lines of sight that share a bin are at most 71 degrees
// apart, so views of the two sides of a thin wall never share one. (Fewer
// bins cannot promise that: the eight octants, for one, hold directions 109
// degrees apart.)
#pragma once

#include <openvdb/Types.h>

#include <array>

namespace levelfuse {

inline constexpr int kSightBins = 12;

/// The centres of the bins (unit vectors).
const std::array<openvdb::Vec3d, kSightBins>& sightBinCentres();

/// The bin of a direction: the nearest centre (need not be unit length; the
/// zero vector is in bin 0).
int sightBin(const openvdb::Vec3d& direction);

/// The bin of every unit direction within the angle asin(sinHalfAngle) of the
/// unit vector `axis` (a round cone: the lines of sight from a centre to a
/// ball), or -1 unless each of them lies in that bin clearly (its centre
/// nearer than any other by more than rounding can change). A dozen dot
/// products, whatever the cone's width.
int sightBinOfRoundCone(const openvdb::Vec3d& axis, double sinHalfAngle);

}  // namespace levelfuse
