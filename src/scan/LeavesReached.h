// levelfuse: which leaf nodes of a grid a range map's windows reach (private
// to the data term's accumulation).
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include "UsableSpans.h"

#include <openvdb/math/BBox.h>
#include <openvdb/math/Coord.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

namespace levelfuse::detail {

/// The most leaves whose bits leavesReached() marks in a dense block by
/// default: 2 MiB of bits.
inline constexpr double kMostDenseLeaves = 16.0 * 1024 * 1024;

/// The origins (in voxels of size `voxelSize`, voxel centres at multiples of
/// it) of the 8^3 leaf nodes that readings of `map` reach within `reach`
/// along their lines of sight, sorted: per tile of 4 x 4 pixels, the lines of
/// sight through it between its nearest reading less the reach and its
/// farthest plus the reach (a box for parallel rays, a frustum for a camera).
/// Marked in a dense block of bits over the tiles' bounds where those span at
/// most `mostDenseLeaves` leaves (a room's frame at 10 mm: some hundred
/// thousand), else in sparse trees; the same leaves either way.
std::vector<openvdb::Coord> leavesReached(const RangeMap& map, double voxelSize, double reach,
                                          double mostDenseLeaves = kMostDenseLeaves);

/// How many leaf nodes leavesReached() marks for `map`, with repeats: the
/// leaves that the box of each tile of pixels spans, summed in doubles. An
/// upper bound of the leaves it returns, and the measure of its work; cheap
/// (no grid), so that a window or a camera that would reach absurdly far is
/// seen before the marking starts; unbounded (HUGE_VAL) where a box reaches
/// leaves whose origins no Coord holds. Expands `reached` by the tiles' boxes.
/// With `xMin` and `xMax` (world), of the boxes cut to that range of x alone.
double leafMarks(const RangeMap& map, double voxelSize, double reach, openvdb::BBoxd& reached,
                 double xMin = -HUGE_VAL, double xMax = HUGE_VAL);

/// Whether readings of the spans' map can reach the leaf at `origin` within
/// `reach`: false if the leaf's depths and the readings of the usable cells
/// over its footprint in the map (UsableSpans::meet) are more than `reach`
/// apart.
bool leafMayBeReached(const UsableSpans& spans, const openvdb::Coord& origin, double voxelSize, double reach);
/// The same for the cube of `dim` voxels a side at `origin` (a leaf's is 8).
bool cubeMayBeReached(const UsableSpans& spans, const openvdb::Coord& origin, int dim, double voxelSize, double reach);
/// Which of the eight cubes of 4^3 voxels of the leaf at `origin` readings of
/// the spans' map may reach (cubeMayBeReached): bit (x / 4) * 4 + (y / 4) * 2
/// + z / 4 for the cube holding local voxel (x, y, z).
std::uint8_t leafCubesMayBeReached(const UsableSpans& spans, const openvdb::Coord& origin, double voxelSize,
                                   double reach);
/// The bit of leafCubesMayBeReached for the voxel at `offset` in its leaf
/// (OpenVDB's order: offset = x * 64 + y * 8 + z).
inline unsigned cubeOfOffset(openvdb::Index offset) {
  return ((offset >> 8) & 1u) << 2 | ((offset >> 5) & 1u) << 1 | ((offset >> 2) & 1u);
}

/// The radius of the ball around the voxel centres of a cube of `dim` voxels
/// a side (world units, or a rigid map's frame).
double cubeBallRadius(double voxelSize, int dim);

/// What RangeMap::sight(x, margin) says at every voxel centre x of the leaf at
/// `origin`, when it says the same everywhere and that can be told from the
/// leaf's corners and the readings over its footprint (the blocks' bounds,
/// else the footprint's own pixels when they are few): kOutside (wholly
/// behind a camera or beside the map's pixels; RangeMap::missesBall first,
/// which spares the projection of the corners), kEmpty (in front of complete
/// readings by more than the margin), kBehind (behind them by more), kUnknown
/// (no pixel of the footprint has a reading, and misses are not empty);
/// nothing when each voxel must be asked. Never says what a voxel's own sight
/// would not (ties within rounding are left to the voxels).
std::optional<RangeMap::Sight> leafSight(const RangeMap& map, const openvdb::Coord& origin, double voxelSize,
                                         double margin);
/// The same for the cube of `dim` voxels a side at `origin` (a leaf's is 8).
std::optional<RangeMap::Sight> cubeSight(const RangeMap& map, const openvdb::Coord& origin, int dim, double voxelSize,
                                         double margin);

}  // namespace levelfuse::detail
