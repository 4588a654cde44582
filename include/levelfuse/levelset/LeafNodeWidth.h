// levelfuse: the width of the leaf nodes of the grids levelfuse builds.
#pragma once

#include <openvdb/openvdb.h>

namespace levelfuse {

/// Width of a leaf node of a FloatTree (voxels), and of every tree levelfuse
/// builds: slabs are cut at its multiples, and a range map's windows are
/// gathered into leaves of it.
inline constexpr openvdb::Int32 kLeafNodeWidth = static_cast<openvdb::Int32>(openvdb::FloatTree::LeafNodeType::DIM);

}  // namespace levelfuse
