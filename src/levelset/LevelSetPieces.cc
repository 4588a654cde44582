// levelfuse: a level set's leaves packed by slab, and put together again.

#include <levelfuse/levelset/LevelSetPieces.h>
#include <levelfuse/levelset/detail/LeafMaskOps.h>

#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace levelfuse {

namespace {

using Leaf = openvdb::FloatTree::LeafNodeType;
constexpr std::size_t kMaskBytes = Leaf::SIZE / 8;
/// Bytes of one packed leaf: origin, active voxels, values.
constexpr std::size_t kLeafBytes = 3 * sizeof(openvdb::Int32) + kMaskBytes + Leaf::SIZE * sizeof(float);

}  // namespace

void addLevelSetLeaves(openvdb::FloatGrid& levelSet, const PackedLeaves& piece) {
  openvdb::FloatTree& tree = levelSet.tree();
  if (piece.size() % kLeafBytes != 0)
    throw std::invalid_argument("addLevelSetLeaves: " + std::to_string(piece.size()) +
                                " bytes of packed leaves are no whole number of leaves (" +
                                std::to_string(kLeafBytes) + " bytes each)");
  for (std::size_t at = 0; at < piece.size(); at += kLeafBytes) {
    const std::uint8_t* p = piece.data() + at;
    openvdb::Int32 origin[3];
    std::memcpy(origin, p, sizeof(origin));
    const openvdb::Coord ijk(origin[0], origin[1], origin[2]);
    if (tree.probeConstLeaf(ijk))
      throw std::invalid_argument("addLevelSetLeaves: two pieces hold the leaf at " + ijk.asVec3i().str());
    Leaf* leaf = tree.touchLeaf(ijk);
    if (leaf->origin() != ijk)
      throw std::invalid_argument("addLevelSetLeaves: " + ijk.asVec3i().str() + " is no leaf node's origin");
    detail::LeafMask active;
    std::memcpy(&detail::maskWord(active, 0), p + sizeof(origin), kMaskBytes);
    leaf->setValueMask(active);
    std::memcpy(leaf->buffer().data(), p + sizeof(origin) + kMaskBytes, Leaf::SIZE * sizeof(float));
  }
}

void closeAssembledLevelSet(openvdb::FloatGrid& levelSet) {
  openvdb::tools::signedFloodFill(levelSet.tree());
  openvdb::tools::pruneLevelSet(levelSet.tree());
}

SlabBounds levelSetReach(const SlabBounds& slab) {
  SlabBounds reach = slab;
  if (slab.hasLower()) reach.begin -= 2 * kLeafNodeWidth;
  if (slab.hasHigher()) reach.end += 2 * kLeafNodeWidth;
  return reach;
}

SlabBounds overlapOf(const SlabBounds& a, const SlabBounds& b) {
  SlabBounds both;
  both.begin = std::max(a.begin, b.begin);
  both.end = std::min(a.end, b.end);
  return both;
}

namespace {

/// The metadata describeLevelSetPiece writes.
constexpr const char* kPieceKey = "levelfuse_piece";
constexpr const char* kPiecesKey = "levelfuse_pieces";
constexpr const char* kPieceBeginKey = "levelfuse_piece_begin_x";
constexpr const char* kPieceEndKey = "levelfuse_piece_end_x";

/// The origins of the leaf nodes of `tree` whose origin x lies in `bounds`
/// (with `within` false: outside it).
template <typename TreeT>
std::vector<openvdb::Coord> leafOrigins(const TreeT& tree, const SlabBounds& bounds, bool within) {
  std::vector<openvdb::Coord> origins;
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf)
    if (bounds.contains(leaf->origin().x()) == within) origins.push_back(leaf->origin());
  return origins;
}

/// Moves the leaf nodes of `from` whose origin x lies in `bounds` into `to`;
/// `caller` names the function in the error for a leaf `to` holds already.
template <typename GridT>
void moveLeavesWithin(GridT& from, const SlabBounds& bounds, GridT& to, const char* caller) {
  using LeafT = typename GridT::TreeType::LeafNodeType;
  for (const openvdb::Coord& origin : leafOrigins(from.tree(), bounds, true)) {
    if (to.tree().template probeConstNode<LeafT>(origin))
      throw std::invalid_argument(std::string(caller) + ": the leaf at " + origin.asVec3i().str() +
                                  " is there already");
    to.tree().addLeaf(from.tree().template stealNode<LeafT>(origin, from.background(), false));
  }
}

template <typename GridT>
void dropLeavesOutsideOf(GridT& grid, const SlabBounds& slab) {
  using LeafT = typename GridT::TreeType::LeafNodeType;
  for (const openvdb::Coord& origin : leafOrigins(grid.tree(), slab, false))
    delete grid.tree().template stealNode<LeafT>(origin, grid.background(), false);
  openvdb::tools::prune(grid.tree());
}

template <typename GridT>
void moveAllLeavesOf(GridT& from, GridT& to) {
  moveLeavesWithin(from, SlabBounds{}, to, "moveAllLeaves");
  openvdb::tools::prune(to.tree());
}

}  // namespace

void moveAllLeaves(openvdb::FloatGrid& from, openvdb::FloatGrid& to) { moveAllLeavesOf(from, to); }
void moveAllLeaves(openvdb::Vec3fGrid& from, openvdb::Vec3fGrid& to) { moveAllLeavesOf(from, to); }

void dropLeavesOutside(openvdb::FloatGrid& grid, const SlabBounds& slab) { dropLeavesOutsideOf(grid, slab); }
void dropLeavesOutside(openvdb::Vec3fGrid& grid, const SlabBounds& slab) { dropLeavesOutsideOf(grid, slab); }

PackedLeaves packLevelSetLeaves(const openvdb::FloatGrid& levelSet, const SlabBounds& bounds) {
  std::size_t leaves = 0;
  for (auto leaf = levelSet.tree().cbeginLeaf(); leaf; ++leaf) leaves += bounds.contains(leaf->origin().x());
  // Allocated once: grown leaf by leaf, the bytes of a slab's level set
  // would move as they doubled and peak at up to three times their size.
  PackedLeaves out;
  out.reserve(leaves * kLeafBytes);
  for (auto leaf = levelSet.tree().cbeginLeaf(); leaf; ++leaf) {
    const openvdb::Coord& o = leaf->origin();
    if (!bounds.contains(o.x())) continue;
    const openvdb::Int32 origin[3] = {o.x(), o.y(), o.z()};
    detail::appendBytes(out, origin, sizeof(origin));
    detail::appendBytes(out, detail::maskWords(leaf->getValueMask()), kMaskBytes);
    detail::appendBytes(out, leaf->buffer().data(), Leaf::SIZE * sizeof(float));
  }
  return out;
}

std::vector<SlabBounds> parcelsOf(const openvdb::FloatTree& tree, const SlabBounds& bounds, std::size_t leaves) {
  if (leaves == 0) throw std::invalid_argument("parcelsOf: a parcel must hold at least one leaf node");
  std::vector<SlabBounds> parcels;
  SlabBounds parcel = bounds;
  std::size_t held = 0;
  for (const auto& [x, count] : leafColumns(tree, bounds)) {
    if (held > 0 && held + count > leaves) {
      parcel.end = x;
      parcels.push_back(parcel);
      parcel = SlabBounds{x, bounds.end};
      held = 0;
    }
    held += count;
  }
  parcels.push_back(parcel);
  return parcels;
}

openvdb::FloatGrid::Ptr assembleLevelSet(std::vector<PackedLeaves> pieces, const openvdb::FloatGrid& like) {
  openvdb::FloatGrid::Ptr out = like.copyWithNewTree();
  for (PackedLeaves& piece : pieces) {
    addLevelSetLeaves(*out, piece);
    PackedLeaves().swap(piece);
  }
  closeAssembledLevelSet(*out);
  return out;
}

void closeLevelSetPiece(openvdb::FloatGrid& piece) {
  openvdb::FloatTree& tree = piece.tree();
  std::vector<openvdb::Coord> origins;
  origins.reserve(tree.leafCount());
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) origins.push_back(leaf->origin());
  std::sort(origins.begin(), origins.end());  // by x, then y, then z: each column's leaves in a run, upwards
  const openvdb::Int32 w = kLeafNodeWidth;
  const float inside = -std::abs(tree.background());
  for (std::size_t i = 0; i + 1 < origins.size(); ++i) {
    const openvdb::Coord& below = origins[i];
    const openvdb::Coord& above = origins[i + 1];
    const bool sameColumn = below.x() == above.x() && below.y() == above.y();
    if (!sameColumn || above.z() == below.z() + w) continue;
    // The cells between two leaves of a column take the side of the voxels facing them.
    if (tree.probeConstLeaf(below)->getValue(below.offsetBy(0, 0, w - 1)) >= 0.0f) continue;
    tree.fill(openvdb::CoordBBox(below.offsetBy(0, 0, w), above.offsetBy(w - 1, w - 1, -1)), inside, false);
  }
  openvdb::tools::pruneLevelSet(tree);
}

void describeLevelSetPiece(openvdb::FloatGrid& piece, int index, int count, const SlabBounds& bounds) {
  piece.insertMeta(kPieceKey, openvdb::Int32Metadata(index));
  piece.insertMeta(kPiecesKey, openvdb::Int32Metadata(count));
  if (bounds.hasLower()) piece.insertMeta(kPieceBeginKey, openvdb::Int32Metadata(bounds.begin));
  if (bounds.hasHigher()) piece.insertMeta(kPieceEndKey, openvdb::Int32Metadata(bounds.end));
}

std::optional<std::pair<int, int>> levelSetPieceOf(const openvdb::FloatGrid& levelSet) {
  const auto index = levelSet.getMetadata<openvdb::Int32Metadata>(kPieceKey);
  const auto count = levelSet.getMetadata<openvdb::Int32Metadata>(kPiecesKey);
  if (!index || !count) return std::nullopt;
  return std::make_pair(index->value(), count->value());
}

void forgetLevelSetPiece(openvdb::FloatGrid& levelSet) {
  for (const char* key : {kPieceKey, kPiecesKey, kPieceBeginKey, kPieceEndKey}) levelSet.removeMeta(key);
}

void moveLevelSetLeaves(openvdb::FloatGrid& from, const SlabBounds& bounds, openvdb::FloatGrid& to) {
  moveLeavesWithin(from, bounds, to, "moveLevelSetLeaves");
}

}  // namespace levelfuse
