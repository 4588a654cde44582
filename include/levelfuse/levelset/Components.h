// levelfuse: connected components of a level set's inside.
#pragma once

#include <openvdb/openvdb.h>

namespace levelfuse {

/// Number of 6-connected components of the inside of a narrow-band level set,
/// counted over its negative active voxels: every inside region is bounded by
/// the band, so each has band voxels, and two regions the band keeps apart
/// are counted apart.
int insideComponents(const openvdb::FloatGrid& grid);

}  // namespace levelfuse
