// levelfuse: space carving as votes that the range maps cast one map at a time.

#include "CarvingVotes.h"

#include <levelfuse/core/Parallel.h>

#include "LeavesReached.h"

#include <array>
#include <stdexcept>
#include <utility>

namespace levelfuse::detail {

namespace {

using openvdb::Coord;
using LeafT = openvdb::FloatTree::LeafNodeType;
constexpr int kLeafDim = static_cast<int>(LeafT::DIM);

}  // namespace

int sightVote(RangeMap::Sight sight, RangeMap::Kind kind) {
  switch (sight) {
    case RangeMap::Sight::kBehind:
      return 1;  // behind and speaking: 2 - 1
    case RangeMap::Sight::kOutside:
      return kind == RangeMap::Kind::kOrthographic ? -1 : 0;  // parallel rays speak for every point
    case RangeMap::Sight::kUnknown:
    case RangeMap::Sight::kEmpty:
      break;
  }
  return -1;  // speaking, not behind
}

PointVotes::PointVotes(std::size_t count, PointAt point)
    : mPoint(std::move(point)), mBalance(count, 0), mEmpty(count, 0) {}

void PointVotes::add(const RangeMap& map, double margin) {
  parallelFor(mBalance.size(), 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      if (mEmpty[i]) continue;
      const RangeMap::Sight s = map.sight(mPoint(i), margin);
      if (s == RangeMap::Sight::kEmpty) mEmpty[i] = 1;
      else mBalance[i] += sightVote(s, map.kind());
    }
  });
}

BlockVotes::BlockVotes(std::vector<Coord> origins, std::vector<Mask> asked, double voxelSize)
    : mVoxelSize(voxelSize) {
  if (origins.size() != asked.size()) throw std::invalid_argument("BlockVotes: one mask per block");
  mBlocks.resize(origins.size());
  for (std::size_t b = 0; b < origins.size(); ++b) {
    Block& block = mBlocks[b];
    block.origin = origins[b];
    block.asked = asked[b];
    std::uint16_t before = 0;
    for (openvdb::Index w = 0; w < Mask::WORD_COUNT; ++w) {
      block.firstOfWord[w] = before;
      before = static_cast<std::uint16_t>(before + openvdb::util::CountOn(block.asked.template getWord<Mask::Word>(w)));
    }
  }
}

std::size_t BlockVotes::Block::rank(openvdb::Index offset) const {
  const Mask::Word word = asked.template getWord<Mask::Word>(offset >> 6);
  const Mask::Word below = (Mask::Word(1) << (offset & 63)) - 1;
  return firstOfWord[offset >> 6] + openvdb::util::CountOn(word & below);
}

void BlockVotes::add(const RangeMap& map, double margin) {
  parallelFor(mBlocks.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b)
      if (!mBlocks[b].empty) addToBlock(mBlocks[b], map, margin);
  });
}

void BlockVotes::addToBlock(Block& block, const RangeMap& map, double margin) const {
  const RangeMap::Sight whole = leafSight(map, block.origin, mVoxelSize, margin);
  if (whole == RangeMap::Sight::kEmpty) {
    block.empty = true;
    return;
  }
  if (whole != RangeMap::Sight::kUnknown) {
    block.uniform += sightVote(whole, map.kind());
    return;
  }
  if (block.voxels.empty()) block.voxels.assign(block.asked.countOn(), 0);
  for (int x = 0; x < kLeafDim; x += kCubeDim)
    for (int y = 0; y < kLeafDim; y += kCubeDim)
      for (int z = 0; z < kLeafDim; z += kCubeDim) addToCube(block, map, margin, Coord(x, y, z));
}

void BlockVotes::addToCube(Block& block, const RangeMap& map, double margin, const Coord& local) const {
  // The asked voxels of the cube that no map has seen empty yet.
  std::array<openvdb::Index, kCubeDim * kCubeDim * kCubeDim> open;
  std::size_t count = 0;
  for (int x = 0; x < kCubeDim; ++x)
    for (int y = 0; y < kCubeDim; ++y)
      for (int z = 0; z < kCubeDim; ++z) {
        const openvdb::Index o = LeafT::coordToOffset(local.offsetBy(x, y, z));
        if (block.asked.isOn(o) && !block.voxelEmpty.isOn(o)) open[count++] = o;
      }
  if (count == 0) return;
  const RangeMap::Sight whole = count > 1 ? cubeSight(map, block.origin + local, kCubeDim, mVoxelSize, margin)
                                          : RangeMap::Sight::kUnknown;
  for (std::size_t i = 0; i < count; ++i) {
    const openvdb::Index o = open[i];
    RangeMap::Sight s = whole;
    if (s == RangeMap::Sight::kUnknown) {
      const openvdb::Vec3d x = (block.origin + LeafT::offsetToLocalCoord(o)).asVec3d() * mVoxelSize;
      s = map.sight(x, margin);
    }
    if (s == RangeMap::Sight::kEmpty) block.voxelEmpty.setOn(o);
    else block.voxels[block.rank(o)] += sightVote(s, map.kind());
  }
}

}  // namespace levelfuse::detail
