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
/// The same, of maps visited one at a time.
AccumulationCost accumulationCost(const RangeMapSequence& maps, double voxelSize, double reach);

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

}  // namespace levelfuse
