// levelfuse: a level set on a grid of half the voxel size.
#pragma once

#include <openvdb/openvdb.h>

namespace levelfuse {

/// Samples `levelSet` trilinearly at the voxel centres of a grid with half its
/// voxel size (same origin), over the leaf nodes of `levelSet`, with its tiles
/// carried over: the coarse-to-fine step of the reconstruction (section 6).
/// The result is a level set whose narrow band keeps the voxels within
/// `halfWidth` fine voxels of the surface. Throws std::invalid_argument for a
/// grid that is not a level set or whose voxels are not uniform.
openvdb::FloatGrid::Ptr refineLevelSet(const openvdb::FloatGrid& levelSet, double halfWidth = 3.0);

}  // namespace levelfuse
