// levelfuse: space carving as votes that the range maps cast one map at a time.

#include "CarvingVotes.h"

#include <levelfuse/core/Parallel.h>
#include <levelfuse/levelset/LeafNodeWidth.h>

#include "LeavesReached.h"

#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>
#include <utility>

namespace levelfuse::detail {

namespace {

using openvdb::Coord;
using LeafT = openvdb::FloatTree::LeafNodeType;

}  // namespace

PointVotes::PointVotes(std::size_t count, PointAt point) : mPoint(std::move(point)), mRecords(count) {}

void PointVotes::add(const RangeMap& map, double margin, std::size_t index) {
  parallelFor(mRecords.size(), 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      Record& r = mRecords[i];
      if (r.empty || r.counted != index) continue;
      r.counted = static_cast<std::uint32_t>(index + 1);
      const RangeMap::Sight s = map.sight(mPoint(i), margin);
      if (s == RangeMap::Sight::kEmpty) r.empty = true;
      else r.balance += sightVote(s, map.raysFromOneCentre());
    }
  });
}

std::size_t PointVotes::firstMapNeeded() const {
  std::size_t first = kNoMapNeeded;
  for (const Record& r : mRecords)
    if (!r.empty) first = std::min<std::size_t>(first, r.counted);
  return first;
}

void BlockVotes::Block::askOnly(const Mask& mask) {
  if (!voxels.empty()) {
    std::vector<std::int32_t> kept;
    kept.reserve(mask.countOn());
    for (auto it = mask.beginOn(); it; ++it) kept.push_back(voxels[rank(it.pos())]);
    voxels = std::move(kept);
  }
  asked = mask;
  everyVoxelAsked = asked.isOn();
  std::uint16_t before = 0;
  for (openvdb::Index w = 0; w < Mask::WORD_COUNT; ++w) {
    firstOfWord[w] = before;
    before = static_cast<std::uint16_t>(before + openvdb::util::CountOn(asked.template getWord<Mask::Word>(w)));
  }
}

BlockVotes::BlockVotes(std::vector<Coord> origins, std::vector<Mask> asked, double voxelSize, Kept* kept)
    : mVoxelSize(voxelSize) {
  if (origins.size() != asked.size()) throw std::invalid_argument("BlockVotes: one mask per block");
  mBlocks.resize(origins.size());
  for (std::size_t b = 0; b < origins.size(); ++b) {
    Block& block = mBlocks[b];
    const auto found = kept ? kept->find(origins[b]) : Kept::iterator();
    // Kept votes answer for the voxels they were cast on alone.
    if (kept && found != kept->end() && (asked[b] & !found->second.asked).isOff()) {
      block = std::move(found->second);
      kept->erase(found);
    } else {
      block.origin = origins[b];
    }
    block.askOnly(asked[b]);
  }
}

void BlockVotes::add(const RangeMap& map, double margin, std::size_t index) {
  parallelFor(mBlocks.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      Block& block = mBlocks[b];
      if (block.empty || block.counted != index) continue;
      block.counted = static_cast<std::uint32_t>(index + 1);
      addToBlock(block, map, margin);
    }
  });
}

std::size_t BlockVotes::firstMapNeeded() const {
  std::size_t first = kNoMapNeeded;
  for (const Block& block : mBlocks)
    if (!block.empty) first = std::min<std::size_t>(first, block.counted);
  return first;
}

void BlockVotes::keepIn(Kept& kept) {
  for (Block& block : mBlocks) kept[block.origin] = std::move(block);
  mBlocks.clear();
}

void BlockVotes::addToBlock(Block& block, const RangeMap& map, double margin) const {
  const std::optional<RangeMap::Sight> whole = leafSight(map, block.origin, mVoxelSize, margin);
  if (whole == RangeMap::Sight::kEmpty) {
    block.empty = true;
    return;
  }
  if (whole) {
    block.uniform += sightVote(*whole, map.raysFromOneCentre());
    return;
  }
  if (block.voxels.empty()) block.voxels.assign(block.asked.countOn(), 0);
  for (int x = 0; x < kLeafNodeWidth; x += kCubeDim)
    for (int y = 0; y < kLeafNodeWidth; y += kCubeDim)
      for (int z = 0; z < kLeafNodeWidth; z += kCubeDim) addToCube(block, map, margin, Coord(x, y, z));
}

void BlockVotes::addToCube(Block& block, const RangeMap& map, double margin, const Coord& local) const {
  // The asked voxels of the cube that no map has seen empty yet, in offset
  // order: a row of the cube along z is kCubeDim neighbouring bits of one
  // word of the masks (a word holds a leaf's 64 voxels of one x).
  constexpr int kCubeVoxels = kCubeDim * kCubeDim * kCubeDim;
  static_assert(kLeafNodeWidth * kLeafNodeWidth == 64 && kCubeDim <= kLeafNodeWidth,
                "a word of the mask is one x of the leaf");
  constexpr Mask::Word kRow = (Mask::Word(1) << kCubeDim) - 1;
  std::array<openvdb::Index, kCubeVoxels> open;
  std::size_t count = 0;
  for (int x = local.x(); x < local.x() + kCubeDim; ++x) {
    const Mask::Word openWord =
        block.asked.template getWord<Mask::Word>(x) & ~block.voxelEmpty.template getWord<Mask::Word>(x);
    for (int y = local.y(); y < local.y() + kCubeDim; ++y) {
      const int shift = y * kLeafNodeWidth + local.z();
      for (Mask::Word row = (openWord >> shift) & kRow; row != 0; row &= row - 1)
        open[count++] = static_cast<openvdb::Index>(x * 64 + shift) + openvdb::util::FindLowestOn(row);
    }
  }
  if (count == 0) return;
  const std::optional<RangeMap::Sight> whole =
      count > 1 ? cubeSight(map, block.origin + local, kCubeDim, mVoxelSize, margin) : std::nullopt;
  std::array<RangeMap::Sight, kCubeVoxels> sight;
  if (!whole) {
    std::array<openvdb::Vec3d, kCubeVoxels> x;
    for (std::size_t i = 0; i < count; ++i)
      x[i] = (block.origin + LeafT::offsetToLocalCoord(open[i])).asVec3d() * mVoxelSize;
    map.sights(x.data(), count, margin, sight.data());
  } else {
    sight.fill(*whole);
  }
  for (std::size_t i = 0; i < count; ++i) {
    const openvdb::Index o = open[i];
    if (sight[i] == RangeMap::Sight::kEmpty) block.voxelEmpty.setOn(o);
    else block.voxels[block.rank(o)] += sightVote(sight[i], map.raysFromOneCentre());
  }
}

void CarvingRecords::keepOnlyFor(double size, double thickness, std::size_t count) {
  if (size != voxelSize || thickness != margin || count < maps) clear();
  voxelSize = size;
  margin = thickness;
  maps = count;
}

void CarvingRecords::clear() {
  blocks.clear();
  centres.clear();
  maps = 0;
}

std::size_t CarvingRecords::memoryBytes() const {
  // A node of a std::map: the value and about four words.
  constexpr std::size_t kNode = 4 * sizeof(void*);
  std::size_t bytes = centres.size() * (sizeof(std::pair<const Coord, PointVotes::Record>) + kNode);
  for (const auto& [origin, block] : blocks)
    bytes += sizeof(std::pair<const Coord, BlockVotes::Block>) + kNode + block.voxels.capacity() * sizeof(std::int32_t);
  return bytes;
}

}  // namespace levelfuse::detail
