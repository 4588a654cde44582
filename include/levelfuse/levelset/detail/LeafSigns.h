// levelfuse: the signs of a leaf's values as bit masks, and the voxels where
// a level set changes sign between face neighbours (its zero crossings), a
// word of 64 voxels at a time; a voxel's face neighbour's value read from the
// leaf itself where it can be.
#pragma once

#include <levelfuse/levelset/detail/LeafMaskOps.h>

#include <openvdb/openvdb.h>

#include <cstdint>

namespace levelfuse::detail {

/// The voxels of `leaf` whose value is negative (inside).
template <typename LeafT>
LeafMask negativeVoxels(const LeafT& leaf) {
  static_assert(LeafT::DIM == 8, "one word of the mask per x slice");
  LeafMask negative;
  const auto* values = leaf.buffer().data();
  for (int x = 0; x < 8; ++x) {
    std::uint64_t word = 0;
    for (int b = 0; b < 64; ++b) word |= std::uint64_t(values[x * 64 + b] < 0) << b;
    maskWord(negative, x) = word;
  }
  return negative;
}

/// The voxels of `leaf` with a face neighbour of the other sign (a value
/// below zero against one not below it), its own negative voxels given
/// (`negative`, negativeVoxels(leaf)). Across the leaf's faces the
/// neighbours are read from the adjacent leaves, or from the tile or the
/// background there, through `acc`: as asking each neighbour's value would.
template <typename Accessor, typename LeafT>
LeafMask zeroCrossingVoxels(const Accessor& acc, const LeafT& leaf, const LeafMask& negative) {
  const LeafMask positive = !negative;
  LeafMask negativeAcross[kFaceCount], positiveAcross[kFaceCount];
  const LeafMask* negativeFaces[kFaceCount];
  const LeafMask* positiveFaces[kFaceCount];
  for (int f = 0; f < kFaceCount; ++f) {
    const openvdb::Coord across = leafAcross(leaf.origin(), f);
    if (const LeafT* neighbour = acc.probeConstLeaf(across)) negativeAcross[f] = negativeVoxels(*neighbour);
    else negativeAcross[f] = LeafMask(acc.getValue(across) < 0);
    positiveAcross[f] = !negativeAcross[f];
    negativeFaces[f] = &negativeAcross[f];
    positiveFaces[f] = &positiveAcross[f];
  }
  return (negative & dilateFaces(positive, positiveFaces)) | (positive & dilateFaces(negative, negativeFaces));
}

/// The same, the leaf's negative voxels found here.
template <typename Accessor, typename LeafT>
LeafMask zeroCrossingVoxels(const Accessor& acc, const LeafT& leaf) {
  return zeroCrossingVoxels(acc, leaf, negativeVoxels(leaf));
}

/// The value of the face neighbour `step` (one of kFaceOffset) of the voxel
/// at `local` in `leaf`: from the leaf's own values where it lies in the leaf,
/// else through `acc`.
template <typename Accessor, typename LeafT>
typename LeafT::ValueType valueBeside(const Accessor& acc, const LeafT& leaf, openvdb::Coord local,
                                      const int (&step)[3]) {
  local.offset(step[0], step[1], step[2]);
  constexpr int kDim = static_cast<int>(LeafT::DIM);
  if (local.x() >= 0 && local.x() < kDim && local.y() >= 0 && local.y() < kDim && local.z() >= 0 && local.z() < kDim)
    return leaf.getValue(LeafT::coordToOffset(local));
  return acc.getValue(leaf.origin() + local);
}

}  // namespace levelfuse::detail
