// levelfuse: the eight voxels around a point, and a grid's values at them read
// from the one leaf that holds all eight where one does (private to the data
// term's sampler).
#pragma once

#include <levelfuse/levelset/LeafNodeWidth.h>

#include "TrilinearCorners.h"

#include <openvdb/openvdb.h>

#include <type_traits>

namespace levelfuse::detail {

/// The eight voxels around a point and their trilinear weights.
struct CellCorners {
  openvdb::Coord ijk[8];
  double t[8];
  openvdb::Vec3d offset[8];  ///< x - p_k, world
  /// One leaf holds all eight: the cell does not cross a leaf's face (343 of
  /// a leaf's 512 cells); then `leafOffset` holds their offsets in it.
  bool oneLeaf = false;
  openvdb::Index leafOffset[8];
};

inline CellCorners cellCornersAround(const openvdb::Vec3d& x, double h) {
  CellCorners c;
  const TrilinearCorners around = trilinearCorners(x / h);
  for (int k = 0; k < 8; ++k) {
    c.ijk[k] = around.ijk[k];
    c.t[k] = around.t[k];
    c.offset[k] = x - c.ijk[k].asVec3d() * h;
  }
  constexpr int kLast = kLeafNodeWidth - 1;
  const openvdb::Coord& lo = c.ijk[0];
  c.oneLeaf = (lo.x() & kLast) != kLast && (lo.y() & kLast) != kLast && (lo.z() & kLast) != kLast;
  if (c.oneLeaf)
    for (int k = 0; k < 8; ++k) c.leafOffset[k] = openvdb::FloatTree::LeafNodeType::coordToOffset(c.ijk[k]);
  return c;
}

/// The leaf-sized block holding `ijk`, as a voxel of a grid of one voxel per
/// leaf node (arithmetic shifts: floor division, also of negative coordinates).
inline openvdb::Coord leafBlockOf(const openvdb::Coord& ijk) {
  constexpr int kLog2 = openvdb::FloatTree::LeafNodeType::LOG2DIM;
  return openvdb::Coord(ijk.x() >> kLog2, ijk.y() >> kLog2, ijk.z() >> kLog2);
}

/// A grid's values at a cell's corners, as its accessor reads them: from the
/// one leaf that holds all eight, found once, where one does (or the one tile
/// or background value there); else voxel by voxel, when asked.
template <typename Accessor>
class CornerValues {
 public:
  using ValueType = typename Accessor::ValueType;
  CornerValues(Accessor& acc, const CellCorners& c) : mAcc(acc), mCorners(c) {
    if (!c.oneLeaf) return;
    mLeaf = acc.probeConstLeaf(c.ijk[0]);
    if (!mLeaf) mUniform = acc.getValue(c.ijk[0]);
  }
  ValueType operator[](int k) const {
    if (!mCorners.oneLeaf) return mAcc.getValue(mCorners.ijk[k]);
    return mLeaf ? mLeaf->getValue(mCorners.leafOffset[k]) : mUniform;
  }

 private:
  using LeafT = typename std::remove_const_t<typename Accessor::TreeType>::LeafNodeType;
  Accessor& mAcc;
  const CellCorners& mCorners;
  const LeafT* mLeaf = nullptr;
  ValueType mUniform{};
};

/// A grid of one voxel per leaf node at a cell's corners: the value of each
/// corner's leaf, read once where one leaf holds all eight.
template <typename Accessor>
class CornerLeafValues {
 public:
  using ValueType = typename Accessor::ValueType;
  CornerLeafValues(Accessor& acc, const CellCorners& c) : mAcc(acc), mCorners(c) {
    if (c.oneLeaf) mOne = acc.getValue(leafBlockOf(c.ijk[0]));
  }
  ValueType operator[](int k) const {
    return mCorners.oneLeaf ? mOne : mAcc.getValue(leafBlockOf(mCorners.ijk[k]));
  }

 private:
  Accessor& mAcc;
  const CellCorners& mCorners;
  ValueType mOne{};
};

}  // namespace levelfuse::detail
