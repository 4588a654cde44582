// levelfuse: what accumulating the data term on a grid costs, known before it
// is done.
//
// Accumulation (ForceField::accumulate, the linear solution, DataTermGrids)
// first marks the leaf nodes each range map's windows reach, tile of pixels by
// tile, then fills every leaf marked. A window far wider than the data, or a
// camera whose lines of sight spread far (a focal length of a thousandth of a
// pixel), makes both grow without bound; this estimate, from the same tiles'
// boxes and without a grid, lets the caller refuse such work up front.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>

#include <cmath>
#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace levelfuse {

struct AccumulationCost {
  /// Leaf nodes marked over all range maps, with repeats: the work of finding
  /// where the windows reach, and at most the (leaf, map) pairs evaluated.
  double leafMarks = 0.0;
  /// Leaf nodes that may hold data: the marks, but no more than the box of
  /// everything the windows reach holds.
  double leaves = 0.0;
  /// Memory at most: the lists of marked leaves per map and the leaves of the
  /// accumulated grids.
  double bytes = 0.0;
};

/// Bytes per leaf marked (its place in the lists of leaves and of (leaf, map) pairs).
inline constexpr double kBytesPerLeafMark = 32.0;
/// Bytes per accumulated leaf node: the sum of the terms and of their weights,
/// a float leaf each, and their bookkeeping.
inline constexpr double kBytesPerAccumulatedLeaf = 4608.0;

/// The cost of accumulating the data term of `maps` on a grid of `voxelSize`
/// whose windows reach `reach` (world units) from their readings.
AccumulationCost accumulationCost(const std::vector<RangeMap>& maps, double voxelSize, double reach);
/// The same, of maps visited one at a time; with `xMin` and `xMax` (world),
/// within that range of x alone (accumulationCostWithin).
AccumulationCost accumulationCost(const RangeMapSequence& maps, double voxelSize, double reach,
                                  double xMin = -HUGE_VAL, double xMax = HUGE_VAL);

/// Where the windows of range maps reach on a grid, found map by map before
/// any is accumulated: the leaf nodes they reach (detail::leavesReached),
/// each once, and each map's first and last column of them.
class ReachedLeaves {
 public:
  /// The first and last x origin (voxels) of the columns of leaf nodes a map
  /// reaches; first > last if it reaches none.
  struct Span {
    openvdb::Int32 first = 1, last = 0;
    bool empty() const { return first > last; }
  };

  ReachedLeaves(double voxelSize, double reach) : mVoxelSize(voxelSize), mReach(reach) {}
  /// Adds the leaves `map`'s windows reach; returns its span.
  Span add(const RangeMap& map);
  /// Adds the leaf nodes of the box `leaves` (in the units of leaves()), e.g. another process's.
  void add(const openvdb::CoordBBox& leaves) { mLeaves.sparseFill(leaves, true, true); }
  /// The leaf nodes reached, one voxel each (index space divided by the leaf's width).
  const openvdb::MaskTree& leaves() const { return mLeaves; }
  /// How many leaf nodes are reached per column: the x origin (voxels) of each
  /// column that has any, and how many, in order of x (balancedSlabs' input).
  std::vector<std::pair<openvdb::Int32, std::size_t>> columns() const;
  /// The box of the leaf nodes reached (voxels): empty if none.
  openvdb::CoordBBox voxelBox() const;

 private:
  double mVoxelSize, mReach;
  openvdb::MaskTree mLeaves;
};

/// The leaf nodes the windows of `maps` reach on a grid of `voxelSize`, each
/// once, counted per column of leaf nodes: the x origin (voxels) of each
/// column that has any, and how many, in order of x (balancedSlabs' input):
/// where along x the data term's leaves, and the surface, lie before any is
/// accumulated.
std::vector<std::pair<openvdb::Int32, std::size_t>> accumulationColumns(const RangeMapSequence& maps, double voxelSize,
                                                                        double reach);

struct PackedScans;

/// The cost of accumulating a set of maps, for a voxel size and a reach: what
/// a memory check asks, once or, to advise a voxel size that fits, again.
using AccumulationCostOf = std::function<AccumulationCost(double voxelSize, double reach)>;
/// Of maps visited one at a time (accumulationCost).
AccumulationCostOf accumulationCostOf(RangeMapSequence maps);
/// Of packed maps, unpacked a few at a time in parallel; the same cost, bit
/// for bit, as visiting them one at a time. `scans` must outlive the function.
AccumulationCostOf accumulationCostOf(const PackedScans& scans);
/// The cost of accumulating a set of maps within the world x range from
/// `xMin` to `xMax` alone (a slab of the data): the marks and the box of the
/// tiles' boxes cut to it. All of x from -HUGE_VAL to HUGE_VAL.
using AccumulationCostWithin = std::function<AccumulationCost(double voxelSize, double reach, double xMin, double xMax)>;
/// Of maps visited one at a time.
AccumulationCostWithin accumulationCostWithin(RangeMapSequence maps);
/// Of packed maps, unpacked a few at a time in parallel. `scans` must outlive the function.
AccumulationCostWithin accumulationCostWithin(const PackedScans& scans);
/// The cost within all of x.
AccumulationCostOf overAllOfX(AccumulationCostWithin costWithin);

}  // namespace levelfuse
