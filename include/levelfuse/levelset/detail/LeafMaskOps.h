// levelfuse: word-level morphology on the 8x8x8 bit masks of leaf nodes.
//
// A leaf mask holds eight 64-bit words, one per x slice; bit y*8+z of word x
// is voxel (x, y, z), matching OpenVDB's leaf offset (x << 6) | (y << 3) | z.
#pragma once

#include <openvdb/util/NodeMasks.h>

#include <array>
#include <cstdint>

namespace levelfuse::detail {

using LeafMask = openvdb::util::NodeMask<3>;

/// Faces of a leaf, in the order -x, +x, -y, +y, -z, +z.
enum Face : int { kFaceXm = 0, kFaceXp, kFaceYm, kFaceYp, kFaceZm, kFaceZp, kFaceCount };

/// The index offsets of a voxel's (or a leaf's, in leaves) six face
/// neighbours, in Face order: every per-face table follows it.
inline constexpr int kFaceOffset[kFaceCount][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0},
                                                   {0, 1, 0},  {0, 0, -1}, {0, 0, 1}};

/// The origin of the leaf across face f of the leaf at `origin`.
inline openvdb::Coord leafAcross(const openvdb::Coord& origin, int f) {
  constexpr int dim = static_cast<int>(LeafMask::DIM);
  return origin.offsetBy(kFaceOffset[f][0] * dim, kFaceOffset[f][1] * dim, kFaceOffset[f][2] * dim);
}

inline std::uint64_t maskWord(const LeafMask& m, int x) { return m.getWord<std::uint64_t>(x); }
inline std::uint64_t& maskWord(LeafMask& m, int x) { return m.getWord<std::uint64_t>(x); }
/// The mask's eight words (a NodeMask holds nothing else).
inline const std::uint64_t* maskWords(const LeafMask& m) {
  return &const_cast<LeafMask&>(m).getWord<std::uint64_t>(0);
}

namespace bits {
constexpr std::uint64_t kZ0 = 0x0101010101010101ULL;  // voxels with z == 0
constexpr std::uint64_t kZ7 = 0x8080808080808080ULL;  // voxels with z == 7
constexpr std::uint64_t kY0 = 0x00000000000000FFULL;  // voxels with y == 0
constexpr std::uint64_t kY7 = 0xFF00000000000000ULL;  // voxels with y == 7
}  // namespace bits

/// The voxels of `self` and their face neighbours (6-connected dilation by one
/// voxel), including neighbours reached from the adjacent leaves' masks.
/// `face[f]` is the mask of the leaf across face f, or null if there is none.
inline LeafMask dilateFaces(const LeafMask& self, const LeafMask* const face[kFaceCount]) {
  using namespace bits;
  LeafMask out;
  for (int x = 0; x < 8; ++x) {
    const std::uint64_t w = maskWord(self, x);
    std::uint64_t d = w | ((w << 1) & ~kZ0) | ((w >> 1) & ~kZ7) | (w << 8) | (w >> 8);
    if (x > 0) d |= maskWord(self, x - 1);
    else if (face[kFaceXm]) d |= maskWord(*face[kFaceXm], 7);
    if (x < 7) d |= maskWord(self, x + 1);
    else if (face[kFaceXp]) d |= maskWord(*face[kFaceXp], 0);
    if (face[kFaceYm]) d |= maskWord(*face[kFaceYm], x) >> 56;
    if (face[kFaceYp]) d |= (maskWord(*face[kFaceYp], x) & kY0) << 56;
    if (face[kFaceZm]) d |= (maskWord(*face[kFaceZm], x) & kZ7) >> 7;
    if (face[kFaceZp]) d |= (maskWord(*face[kFaceZp], x) & kZ0) << 7;
    maskWord(out, x) = d;
  }
  return out;
}

/// The voxels of a leaf on its face f.
inline const LeafMask& faceVoxels(int f) {
  using namespace bits;
  static const auto kFaces = [] {
    std::array<LeafMask, kFaceCount> faces;
    for (int face = 0; face < kFaceCount; ++face)
      for (int x = 0; x < 8; ++x) {
        std::uint64_t w = 0;
        switch (face) {
          case kFaceXm: w = x == 0 ? ~0ULL : 0; break;
          case kFaceXp: w = x == 7 ? ~0ULL : 0; break;
          case kFaceYm: w = kY0; break;
          case kFaceYp: w = kY7; break;
          case kFaceZm: w = kZ0; break;
          default: w = kZ7; break;
        }
        maskWord(faces[face], x) = w;
      }
    return faces;
  }();
  return kFaces[f];
}

/// True if any voxel of `m` lies on face f of the leaf.
inline bool touchesFace(const LeafMask& m, int f) {
  const std::uint64_t* a = maskWords(m);
  const std::uint64_t* b = maskWords(faceVoxels(f));
  std::uint64_t any = 0;
  for (int x = 0; x < 8; ++x) any |= a[x] & b[x];
  return any != 0;
}

/// Calls f(offset) for every voxel of `m`, in increasing offset order.
template <typename F>
inline void forEachOn(const LeafMask& m, F&& f) {
  for (int x = 0; x < 8; ++x) {
    std::uint64_t w = maskWord(m, x);
    while (w) {
      const int bit = __builtin_ctzll(w);
      f(static_cast<unsigned>((x << 6) | bit));
      w &= w - 1;
    }
  }
}

inline bool anyOn(const LeafMask& m) {
  std::uint64_t any = 0;
  for (int x = 0; x < 8; ++x) any |= maskWord(m, x);
  return any != 0;
}

}  // namespace levelfuse::detail
