// levelfuse: a level set made in pieces along x and put together again.
//
// The processes that share an evolution slab by slab (SlabField.h) each make
// the output level set's leaf nodes of their own slab (SlabField::toLevelSet
// with fresh ghosts is the whole field's there); one process puts them
// together. Only the leaves travel: the tiles between them follow from the
// leaves by flood fill, as OpenVDB's level sets are built, so the assembled
// level set is the one the whole field makes, bit for bit (tested).
#pragma once

#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/TilesBesideLeaves.h>

#include <openvdb/openvdb.h>

#include <optional>
#include <utility>
#include <vector>

namespace levelfuse {

/// The x range of the level set that SlabField::fromLevelSet reads for the
/// slab `slab`: its own leaves, its ghosts and, for the voxels beside the
/// ghosts, one more column of leaf nodes beyond each neighbour.
SlabBounds levelSetReach(const SlabBounds& slab);

/// The x that lie in both (an empty range, begin >= end, if none do).
SlabBounds overlapOf(const SlabBounds& a, const SlabBounds& b);

/// Lets go of the leaf nodes of `grid` whose origin x lies outside `slab`
/// and prunes it: a grid of leaves on the background (a weight or colour
/// grid beside a level set) cut down to the slab. Unlike Tree::clip, it adds
/// no nodes of background beyond the slab.
void dropLeavesOutside(openvdb::FloatGrid& grid, const SlabBounds& slab);
void dropLeavesOutside(openvdb::Vec3fGrid& grid, const SlabBounds& slab);

/// Moves every leaf node of `from` into `to` (which holds none at their
/// origins) and prunes `to`: the pieces of a weight or colour grid, whose
/// leaves lie on the background, put together.
void moveAllLeaves(openvdb::FloatGrid& from, openvdb::FloatGrid& to);
void moveAllLeaves(openvdb::Vec3fGrid& from, openvdb::Vec3fGrid& to);

/// The leaf nodes of `levelSet` whose origin x lies in `bounds`, their values
/// and active voxels, packed as bytes for another process.
PackedLeaves packLevelSetLeaves(const openvdb::FloatGrid& levelSet, const SlabBounds& bounds);

/// `bounds` cut along x, between columns of leaf nodes, into ranges that
/// together are `bounds`, each holding at most `leaves` of `tree`'s leaf nodes
/// (a column of more is a range of its own): a slab's leaves in parcels small
/// enough to pack and send one at a time. One range, `bounds`, if the tree
/// has no leaf there. Throws std::invalid_argument for `leaves` = 0.
std::vector<SlabBounds> parcelsOf(const openvdb::FloatTree& tree, const SlabBounds& bounds, std::size_t leaves);

/// The level set of the leaves of every piece (packLevelSetLeaves of slabs
/// that together cover x; any order), each piece let go once its leaves are
/// in. It takes `like`'s transform, name, class, metadata and background; its
/// tiles are flood filled from the leaves, and it is pruned as a level set.
/// Throws std::invalid_argument for a piece that is no whole number of
/// leaves, or a leaf that two pieces hold.
openvdb::FloatGrid::Ptr assembleLevelSet(std::vector<PackedLeaves> pieces, const openvdb::FloatGrid& like);

/// The same, one piece at a time, as the pieces arrive: each piece's leaves
/// added to `levelSet` (an empty tree of the level set's settings, e.g.
/// copyWithNewTree of one slab's level set) and, once all are in, its tiles
/// flood filled and the level set pruned.
void addLevelSetLeaves(openvdb::FloatGrid& levelSet, const PackedLeaves& piece);
void closeAssembledLevelSet(openvdb::FloatGrid& levelSet);

/// Makes `piece`, which holds the leaf nodes of a level set whose origin x
/// lies in one slab and nothing else, that level set within the slab: its
/// tiles inside the surface are set, as inactive tiles of -background, and
/// it is pruned as a level set. A slab holds whole columns of leaf nodes
/// along z, so the side of every cell is its own to know: a cell without a
/// leaf lies inside if the nearest leaf below it in its column faces it with
/// inside voxels, and outside if none lies below (a line along z that meets
/// no band never crosses the surface). The pieces of every slab together
/// (their CSG union) are the whole level set, tested against it clipped.
void closeLevelSetPiece(openvdb::FloatGrid& piece);

/// Says in `piece`'s metadata which piece it is: levelfuse_piece (0 to
/// count - 1, along x), levelfuse_pieces (count), and the x range of index
/// space it holds, levelfuse_piece_begin_x and levelfuse_piece_end_x (the
/// end excluded; each left out where the piece reaches to infinity).
void describeLevelSetPiece(openvdb::FloatGrid& piece, int index, int count, const SlabBounds& bounds);
/// Which piece `levelSet` is and of how many, as describeLevelSetPiece said;
/// none for a level set that is no piece.
std::optional<std::pair<int, int>> levelSetPieceOf(const openvdb::FloatGrid& levelSet);
/// Removes what describeLevelSetPiece wrote: the pieces put together are no piece.
void forgetLevelSetPiece(openvdb::FloatGrid& levelSet);

/// Moves the leaf nodes of `from` whose origin x lies in `bounds` into `to`
/// (an empty tree, or one holding none of them): this process's own piece,
/// which needs no copy. `from` keeps inactive tiles in their place.
void moveLevelSetLeaves(openvdb::FloatGrid& from, const SlabBounds& bounds, openvdb::FloatGrid& to);

}  // namespace levelfuse
