// levelfuse: space carving as votes that the range maps cast one map at a time.

#include "CarvingVotes.h"

#include <levelfuse/core/Parallel.h>

#include "LeavesReached.h"

#include <stdexcept>
#include <utility>

namespace levelfuse::detail {

namespace {

using openvdb::Coord;
using LeafT = openvdb::FloatTree::LeafNodeType;

}  // namespace

int sightVote(RangeMap::Sight sight, RangeMap::Kind kind) {
  switch (sight) {
    case RangeMap::Sight::kBehind:
      return 1;  // behind and speaking: 2 - 1
    case RangeMap::Sight::kOutside:
      return kind == RangeMap::Kind::kPinhole ? 0 : -1;  // parallel rays speak for every point
    case RangeMap::Sight::kUnknown:
    case RangeMap::Sight::kEmpty:
      break;
  }
  return -1;  // speaking, not behind
}

PointVotes::PointVotes(std::vector<openvdb::Vec3d> points)
    : mPoints(std::move(points)), mBalance(mPoints.size(), 0), mEmpty(mPoints.size(), 0) {}

void PointVotes::add(const RangeMap& map, double margin) {
  parallelFor(mPoints.size(), 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      if (mEmpty[i]) continue;
      const RangeMap::Sight s = map.sight(mPoints[i], margin);
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
    mBlocks[b].origin = origins[b];
    mBlocks[b].asked = asked[b];
  }
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
  std::size_t k = 0;
  for (auto it = block.asked.beginOn(); it; ++it, ++k) {
    if (block.voxelEmpty.isOn(it.pos())) continue;
    const openvdb::Vec3d x = (block.origin + LeafT::offsetToLocalCoord(it.pos())).asVec3d() * mVoxelSize;
    const RangeMap::Sight s = map.sight(x, margin);
    if (s == RangeMap::Sight::kEmpty) block.voxelEmpty.setOn(it.pos());
    else block.voxels[k] += sightVote(s, map.kind());
  }
}

}  // namespace levelfuse::detail
