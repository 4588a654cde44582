// levelfuse: the eight voxels around a point, and a grid's values at them read
// from each leaf node that holds some of them, found once (private to the
// data term's sampler).
#pragma once

#include <levelfuse/levelset/LeafNodeWidth.h>

#include "TrilinearCorners.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <type_traits>

namespace levelfuse::detail {

/// The eight voxels around a point and their trilinear weights, with the
/// leaf nodes that hold them: one where the cell does not cross a leaf's face
/// (343 of a leaf's 512 cells), else two, four or eight.
struct CellCorners {
  openvdb::Coord ijk[8];
  double t[8];
  openvdb::Vec3d offset[8];  ///< x - p_k, world
  /// Corner k lies in the cell's leaf leafOf[k], at offset leafOffset[k] in
  /// it: the corners of one leaf share the index of its first corner (0 to 7).
  std::uint8_t leafOf[8];
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
  // The corners (k & 1, (k >> 1) & 1, k >> 2) from the lowest cross into the
  // next leaf along an axis where the lowest lies on the leaf's last voxel.
  constexpr int kLast = kLeafNodeWidth - 1;
  const openvdb::Coord& lo = c.ijk[0];
  const int crosses = ((lo.x() & kLast) == kLast ? 1 : 0) | ((lo.y() & kLast) == kLast ? 2 : 0) |
                      ((lo.z() & kLast) == kLast ? 4 : 0);
  for (int k = 0; k < 8; ++k) {
    c.leafOf[k] = static_cast<std::uint8_t>(k & crosses);
    c.leafOffset[k] = openvdb::FloatTree::LeafNodeType::coordToOffset(c.ijk[k]);
  }
  return c;
}

/// The leaf-sized block holding `ijk`, as a voxel of a grid of one voxel per
/// leaf node (arithmetic shifts: floor division, also of negative coordinates).
inline openvdb::Coord leafBlockOf(const openvdb::Coord& ijk) {
  constexpr int kLog2 = openvdb::FloatTree::LeafNodeType::LOG2DIM;
  return openvdb::Coord(ijk.x() >> kLog2, ijk.y() >> kLog2, ijk.z() >> kLog2);
}

/// A grid's values at a cell's corners, as its accessor reads them: from
/// each leaf that holds some of the eight, found once (or the one tile or
/// background value there).
template <typename Accessor>
class CornerValues {
 public:
  using ValueType = typename Accessor::ValueType;
  CornerValues(Accessor& acc, const CellCorners& c) : mCorners(c) {
    for (int k = 0; k < 8; ++k) {
      const int l = c.leafOf[k];
      if (l != k) continue;  // the leaf's first corner finds it
      mLeaf[l] = acc.probeConstLeaf(c.ijk[k]);
      if (!mLeaf[l]) mUniform[l] = acc.getValue(c.ijk[k]);
    }
  }
  ValueType operator[](int k) const {
    const LeafT* leaf = mLeaf[mCorners.leafOf[k]];
    return leaf ? leaf->getValue(mCorners.leafOffset[k]) : mUniform[mCorners.leafOf[k]];
  }

 private:
  using LeafT = typename std::remove_const_t<typename Accessor::TreeType>::LeafNodeType;
  const CellCorners& mCorners;
  const LeafT* mLeaf[8] = {};
  ValueType mUniform[8]{};
};

/// A grid of one voxel per leaf node at a cell's corners: the value of each
/// corner's leaf, read once per leaf.
template <typename Accessor>
class CornerLeafValues {
 public:
  using ValueType = typename Accessor::ValueType;
  CornerLeafValues(Accessor& acc, const CellCorners& c) : mCorners(c) {
    for (int k = 0; k < 8; ++k)
      if (c.leafOf[k] == k) mValue[k] = acc.getValue(leafBlockOf(c.ijk[k]));
  }
  ValueType operator[](int k) const { return mValue[mCorners.leafOf[k]]; }

 private:
  const CellCorners& mCorners;
  ValueType mValue[8]{};
};

}  // namespace levelfuse::detail
