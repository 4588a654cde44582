// levelfuse: space carving as votes that the range maps cast one map at a
// time (private to the linear solution).
//
// A point is outside if some line of sight saw it as empty; else inside if
// more than half of the range maps that speak for it see it behind their
// readings (RangeMap::sight with the window's reach as margin). A scan of
// parallel rays frames an object and speaks for every point; a depth frame is
// a window onto a scene that goes on beyond it, and speaks only for the points
// its lines of sight pass: behind a room's wall, which few of the room's
// frames see, is solid, not a sheet as thin as the window's reach. (A point
// one range map sees behind a grazing surface, while the others cannot tell,
// is not taken for solid.)
//
// Each map adds its votes and may then be released: the votes are the
// balance 2 behind - speaking and whether some map saw the point empty, so
// the answer does not depend on the order of the maps, and a sequence of
// maps held nowhere at once (decompressed one by one) gives the same answer
// as a vector of them. The maps are numbered in their sequence's order; each
// point and block counts the maps whose votes it holds, so votes kept from an
// answer on fewer maps (CarvingRecords) take the rest of the maps alone.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace levelfuse::detail {

/// How one map's sight of a point changes its balance 2 behind - speaking;
/// kEmpty is told apart (the point is outside whatever the others say).
/// Parallel rays (`raysFromOneCentre` false) speak for every point, also
/// those outside their map.
inline int sightVote(RangeMap::Sight sight, bool raysFromOneCentre) {
  switch (sight) {
    case RangeMap::Sight::kBehind:
      return 1;  // behind and speaking: 2 - 1
    case RangeMap::Sight::kOutside:
      return raysFromOneCentre ? 0 : -1;  // parallel rays speak for every point
    case RangeMap::Sight::kUnknown:
    case RangeMap::Sight::kEmpty:
      break;
  }
  return -1;  // speaking, not behind
}

/// The first map a set of votes still needs when none does.
inline constexpr std::size_t kNoMapNeeded = std::numeric_limits<std::size_t>::max();

/// The votes on single points, `point(i)` the i-th of `count` (world units).
class PointVotes {
 public:
  using PointAt = std::function<openvdb::Vec3d(std::size_t)>;
  /// One point's votes.
  struct Record {
    std::int32_t balance = 0;  ///< 2 behind - speaking, of the maps counted
    bool empty = false;        ///< some map saw it empty (or it is not asked)
    std::uint32_t counted = 0;  ///< the maps 0 to counted - 1 have voted
  };
  PointVotes(std::size_t count, PointAt point);
  /// Adds the votes of `map`, the map numbered `index` of its sequence, on
  /// the points that have counted the maps before it alone (margin: the
  /// window's reach). Parallel over the points.
  void add(const RangeMap& map, double margin, std::size_t index);
  /// The first map some point has not counted, or kNoMapNeeded.
  std::size_t firstMapNeeded() const;
  /// Point i is not asked (and is not inside).
  void skip(std::size_t i) { mRecords[i].empty = true; }
  /// Point i's votes are `kept` (votes of the same point).
  void restore(std::size_t i, const Record& kept) { mRecords[i] = kept; }
  const Record& record(std::size_t i) const { return mRecords[i]; }
  /// Whether carving puts point i inside.
  bool inside(std::size_t i) const { return !mRecords[i].empty && mRecords[i].balance > 0; }
  std::size_t size() const { return mRecords.size(); }

 private:
  PointAt mPoint;
  std::vector<Record> mRecords;
};

/// The votes on chosen voxels of leaf-sized blocks: a map that says the
/// same of a whole block (leafSight) votes once for all of its voxels, the
/// others voxel by voxel.
class BlockVotes {
 public:
  using Mask = openvdb::FloatTree::LeafNodeType::NodeMaskType;
  struct Block;
  /// Blocks kept from earlier votes, by origin.
  using Kept = std::map<openvdb::Coord, Block>;
  /// Blocks at `origins` (voxels of size `voxelSize`), each asking of the
  /// voxels in its mask. A block `kept` holds, and whose asked voxels
  /// include the mask's, starts from its votes there (taken out of `kept`).
  BlockVotes(std::vector<openvdb::Coord> origins, std::vector<Mask> asked, double voxelSize, Kept* kept = nullptr);
  /// Adds the votes of `map`, the map numbered `index` of its sequence, on
  /// the blocks that have counted the maps before it alone (margin: the
  /// window's reach). Parallel over the blocks.
  void add(const RangeMap& map, double margin, std::size_t index);
  /// The first map some block has not counted, or kNoMapNeeded.
  std::size_t firstMapNeeded() const;
  /// Moves every block's votes into `kept`.
  void keepIn(Kept& kept);
  /// Calls visit(offset, inside) for every asked voxel of block b, in order.
  template <typename Visit>
  void forEachAsked(std::size_t b, const Visit& visit) const {
    const Block& block = mBlocks[b];
    std::size_t k = 0;
    for (auto it = block.asked.beginOn(); it; ++it, ++k) {
      const std::int32_t balance = block.uniform + (block.voxels.empty() ? 0 : block.voxels[k]);
      visit(it.pos(), !block.empty && !block.voxelEmpty.isOn(it.pos()) && balance > 0);
    }
  }
  /// The side (voxels) of the cubes a block a map cannot speak for at once is
  /// split into before its voxels are asked one by one.
  static constexpr int kCubeDim = 4;
  std::size_t size() const { return mBlocks.size(); }
  const openvdb::Coord& origin(std::size_t b) const { return mBlocks[b].origin; }

  /// One block's votes.
  struct Block {
    openvdb::Coord origin;
    Mask asked;
    std::array<std::uint16_t, Mask::WORD_COUNT> firstOfWord{};  ///< asked voxels before each word of the mask
    bool empty = false;           ///< some map saw the whole block empty
    std::int32_t uniform = 0;     ///< the balance of the maps that spoke for the whole block
    Mask voxelEmpty;              ///< asked voxels some map saw empty
    std::vector<std::int32_t> voxels;  ///< per asked voxel in order, the others' balance (allocated when first needed)
    bool everyVoxelAsked = false;  ///< then an asked voxel's place in `voxels` is its offset
    std::uint32_t counted = 0;     ///< the maps 0 to counted - 1 have voted
    /// Asks of the voxels of `mask` alone (within those asked so far).
    void askOnly(const Mask& mask);
    /// The place of asked voxel `offset` in `voxels`.
    std::size_t rank(openvdb::Index offset) const {
      if (everyVoxelAsked) return offset;
      const Mask::Word word = asked.template getWord<Mask::Word>(offset >> 6);
      const Mask::Word below = (Mask::Word(1) << (offset & 63)) - 1;
      return firstOfWord[offset >> 6] + openvdb::util::CountOn(word & below);
    }
  };

 private:
  void addToBlock(Block& block, const RangeMap& map, double margin) const;
  /// The votes of `map` on the asked voxels of the cube of kCubeDim voxels a
  /// side at `local` in the block: at once where it says the same of all of
  /// them (cubeSight), else voxel by voxel.
  void addToCube(Block& block, const RangeMap& map, double margin, const openvdb::Coord& local) const;

  std::vector<Block> mBlocks;
  double mVoxelSize;
};

/// Carving's votes kept from one linear solution to the next of a sequence
/// of maps that grows between them (CarvingMemo): the votes on the voxels of
/// blocks and on blocks' centres, each with the maps it has counted.
struct CarvingRecords {
  double voxelSize = 0.0;
  double margin = 0.0;
  std::size_t maps = 0;  ///< the maps of the last answer: a sequence with fewer is another one
  BlockVotes::Kept blocks;
  std::map<openvdb::Coord, PointVotes::Record> centres;  ///< by block (origin / leaf width)
  std::mutex answering;  ///< held by the answer that uses the records

  /// Forgets every vote unless they were cast on voxels of `size` with
  /// readings `thickness` thick, by the first maps of a sequence of `count`.
  void keepOnlyFor(double size, double thickness, std::size_t count);
  void clear();
  std::size_t memoryBytes() const;
};

}  // namespace levelfuse::detail
