// levelfuse: branch-free access to a voxel's neighbours across leaf faces.
//
// A leaf and its 26 neighbours form a 3x3x3 block of leaves, numbered by
// neighbourSlot(). Where each neighbour of a voxel of the centre leaf lives
// depends only on the voxel's offset, so it comes from static tables; a missing
// neighbour leaf reads as the static empty leaf (zero values, no voxels in any
// mask), so no access needs a branch on the leaf boundary.
#pragma once

#include <levelfuse/levelset/detail/SparseFieldState.h>

#include <levelfuse/levelset/Stencil.h>

#include <algorithm>
#include <cstdint>
#include <limits>

namespace levelfuse::detail {

/// Values and mask words of the empty leaf that stands in for missing neighbours.
const float* emptyLeafValues();
const std::uint64_t* emptyLeafMaskWords();

/// Where a neighbour of a voxel lives: its leaf's slot in the 3x3x3 block of
/// leaves and its offset in that leaf.
struct NeighbourAddress {
  std::uint16_t offset;
  std::uint8_t slot;
};

/// Table of the six face neighbours of every voxel offset: entries 6 * offset
/// to 6 * offset + 5, in Face order (kFaceOffset).
const NeighbourAddress* faceNeighbourTable();

/// The layer rule of section 5, step 3: a voxel entering a layer takes the
/// value of its nearest inner neighbour plus one voxel outside, minus one
/// voxel inside. NearestInner chooses that neighbour among the values offered
/// one by one: in OpenVDB's sign the smallest value outside and the largest
/// inside (the smallest signed distance from the front); -+max float (inside,
/// outside) if none is offered.
class NearestInner {
 public:
  explicit NearestInner(bool inside) : mSign(inside ? -1.0f : 1.0f) {}
  void offer(float value) { mBest = std::min(mBest, mSign * value); }
  float value() const { return mSign * mBest; }

 private:
  float mSign;
  float mBest = std::numeric_limits<float>::max();
};
/// The value the rule gives a voxel whose nearest inner neighbour holds `nearestInner`.
inline float layerValue(float nearestInner, bool inside, float dx) {
  return inside ? nearestInner - dx : nearestInner + dx;
}
/// Table of the 19 stencil points (Stencil::Index order) of every voxel offset:
/// entries Stencil::kSize * offset onward.
const NeighbourAddress* stencilNeighbourTable();

/// Value buffers of a leaf's 3x3x3 neighbourhood.
class ValueNeighbourhood {
 public:
  ValueNeighbourhood(const LeafTable& table, const LeafRecord& record) {
    for (int s = 0; s < 27; ++s) {
      const std::int32_t n = record.neighbour[s];
      mValues[s] = n >= 0 ? table[n].values : emptyLeafValues();
    }
  }

  /// The 19-point stencil (Stencil.h) of the voxel at `offset`.
  void gather(unsigned offset, Stencil& s) const {
    const NeighbourAddress* at = mStencil + Stencil::kSize * offset;
#pragma GCC unroll 19
    for (int p = 0; p < Stencil::kSize; ++p) s.u[p] = mValues[at[p].slot][at[p].offset];
  }

 private:
  const float* mValues[27];
  const NeighbourAddress* mStencil = stencilNeighbourTable();
};

/// Values and one chosen layer mask of a leaf's face neighbours, for the
/// 6-neighbour rules of the layer updates.
class FaceNeighbourhood {
 public:
  /// `maskOf(record)` selects the mask to read from each leaf record.
  template <typename MaskOf>
  FaceNeighbourhood(const LeafTable& table, const LeafRecord& record, MaskOf maskOf) {
    for (int s = 0; s < 27; ++s) {
      mValues[s] = emptyLeafValues();
      mMask[s] = emptyLeafMaskWords();
    }
    for (int f = 0; f < kFaceCount; ++f) set(table, record.neighbour[kFaceSlot[f]], kFaceSlot[f], maskOf);
    set(table, record.neighbour[kSelfSlot], kSelfSlot, maskOf);
  }

  /// Value of the neighbour in the mask nearest the front (NearestInner).
  float nearest(unsigned offset, bool inside) const {
    const NeighbourAddress* at = mFace + kFaceCount * offset;
    NearestInner best(inside);
#pragma GCC unroll 6
    for (int k = 0; k < kFaceCount; ++k) {
      const unsigned slot = at[k].slot, o = at[k].offset;
      // Only neighbours in the mask are read: the others' leaves are often cold.
      if ((mMask[slot][o >> 6] >> (o & 63u)) & 1u) best.offer(mValues[slot][o]);
    }
    return best.value();
  }

 private:
  template <typename MaskOf>
  void set(const LeafTable& table, std::int32_t n, int slot, MaskOf maskOf) {
    if (n < 0) return;
    mValues[slot] = table[n].values;
    mMask[slot] = maskWords(maskOf(table[n]));
  }
  const float* mValues[27];
  const std::uint64_t* mMask[27];
  const NeighbourAddress* mFace = faceNeighbourTable();
};

}  // namespace levelfuse::detail
