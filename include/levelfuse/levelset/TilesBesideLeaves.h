// levelfuse: the tiles beside a level set's leaves, set from the leaves alone,
// where a slab's level set or a level set put together from pieces
// (LevelSetPieces.h) cannot flood fill them.
#pragma once

#include <openvdb/openvdb.h>

namespace levelfuse {

/// Sets every leaf-sized cell beside a leaf of `grid` (face, edge or corner)
/// that holds no leaf to an inactive tile of the side of the leaf voxel
/// nearest it. Those voxels lie beyond the band or at its edge, and a voxel
/// beyond the band lies on the side of its neighbours, so every leaf beside a
/// cell agrees. A slab's flood fill could not see the band beyond its ghosts;
/// the level set of a slab put together from pieces that cover only its reach
/// (levelSetReach, LevelSetPieces.h) takes its tiles so too, which is all
/// the slab reads.
void setTilesBesideLeaves(openvdb::FloatGrid& grid);

}  // namespace levelfuse
