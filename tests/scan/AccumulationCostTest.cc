// What accumulating the data term costs, known before it is done.

#include "../../src/scan/LeavesReached.h"

#include <levelfuse/scan/AccumulationCost.h>
#include <levelfuse/scan/ForceField.h>
#include <levelfuse/scan/PackedRangeMap.h>
#include <levelfuse/synth/Synth.h>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

std::vector<RangeMap> sphereViews() {
  std::vector<RangeMap> maps;
  const auto sphere = [](const Vec3d& p) { return p.length() - 1.0; };
  for (const synth::View& view : synth::sixAxisViews(Vec3d(0.0), 2.4, 60))
    maps.push_back(synth::renderDistanceFunction(sphere, view, synth::Noise{}, 0.01));
  return maps;
}

TEST(AccumulationCost, BoundsTheLeavesThatAccumulationFills) {
  const std::vector<RangeMap> maps = sphereViews();
  for (const double voxel : {0.02, 0.05}) {
    const ForceField field(maps, defaultForceFieldOptions(maps, voxel));
    const AccumulatedField accumulated = field.accumulate(voxel);
    const AccumulationCost cost = accumulationCost(maps, voxel, field.options().dataWindow().reach());
    const double filled = static_cast<double>(accumulated.g->tree().leafCount());
    EXPECT_GE(cost.leaves, filled) << voxel;
    EXPECT_GE(cost.leafMarks, cost.leaves) << voxel;
    EXPECT_GE(cost.leafMarks * 512.0, static_cast<double>(accumulated.evaluations)) << voxel;
    EXPECT_LT(cost.leaves, 20.0 * filled) << voxel;  // an upper bound, but not a wild one
    EXPECT_DOUBLE_EQ(cost.bytes, kBytesPerLeafMark * cost.leafMarks + kBytesPerAccumulatedLeaf * cost.leaves);
  }
}

TEST(AccumulationCost, SeesAWindowThatReachesAbsurdlyFar) {
  const std::vector<RangeMap> maps = sphereViews();
  const double modest = accumulationCost(maps, 0.02, 0.06).bytes;
  EXPECT_GT(accumulationCost(maps, 0.02, 1e6).bytes, 1e6 * modest);  // 190 TiB: more than any machine has
  EXPECT_EQ(accumulationCost(maps, 0.02, 1e300).bytes, HUGE_VAL);  // no box of leaves counts that far
}

TEST(AccumulationCost, OfPackedMapsIsTheSameWhateverTheThreads) {
  PackedScans packed;
  for (RangeMap& map : sphereViews()) packed.add(std::move(map));
  const std::vector<RangeMap> maps = sphereViews();
  for (const double reach : {0.06, 1e6, 1e300})
    for (const int threads : {1, 2, 3}) {
      const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      const AccumulationCost visited = accumulationCostOf(rangeMapsOf(maps))(0.02, reach);
      const AccumulationCost unpacked = accumulationCostOf(packed)(0.02, reach);
      EXPECT_EQ(unpacked.leafMarks, visited.leafMarks) << reach << ", " << threads;
      EXPECT_EQ(unpacked.leaves, visited.leaves) << reach << ", " << threads;
      EXPECT_EQ(unpacked.bytes, visited.bytes) << reach << ", " << threads;
    }
}

TEST(AccumulationCost, WithinARangeOfXCountsThatPartAlone) {
  // A slab's cost: the tiles' boxes cut to its range of x. The two halves at
  // x = 0 each cost less than the whole and together no less (a leaf across
  // the cut counts in both); all of x is the whole; packed maps count alike.
  PackedScans packed;
  for (RangeMap& map : sphereViews()) packed.add(std::move(map));
  const std::vector<RangeMap> maps = sphereViews();
  const double voxel = 0.02, reach = 0.06;
  const AccumulationCost whole = accumulationCost(maps, voxel, reach);
  const AccumulationCostWithin visited = accumulationCostWithin(rangeMapsOf(maps));
  const AccumulationCostWithin unpacked = accumulationCostWithin(packed);
  EXPECT_EQ(visited(voxel, reach, -HUGE_VAL, HUGE_VAL).bytes, whole.bytes);
  EXPECT_EQ(overAllOfX(unpacked)(voxel, reach).bytes, whole.bytes);
  const AccumulationCost below = visited(voxel, reach, -HUGE_VAL, 0.0), above = visited(voxel, reach, 0.0, HUGE_VAL);
  EXPECT_LT(below.leafMarks, 0.75 * whole.leafMarks);
  EXPECT_LT(above.leafMarks, 0.75 * whole.leafMarks);
  EXPECT_GE(below.leafMarks + above.leafMarks, whole.leafMarks);
  EXPECT_LT(below.leaves, whole.leaves);
  EXPECT_EQ(unpacked(voxel, reach, -HUGE_VAL, 0.0).bytes, below.bytes);
  EXPECT_EQ(visited(voxel, reach, 5.0, 6.0).bytes, 0.0) << "no data there";
}

TEST(AccumulationCost, ColumnsHoldEveryLeafThatAccumulationFills) {
  // Per column of leaf nodes along x: each leaf the windows reach, once. Every
  // leaf that accumulation fills is among them, and no column holds more than
  // the leaves its box spans or the marks count.
  const std::vector<RangeMap> maps = sphereViews();
  for (const double voxel : {0.02, 0.05}) {
    const ForceField field(maps, defaultForceFieldOptions(maps, voxel));
    const double reach = field.options().dataWindow().reach();
    const auto columns = accumulationColumns(rangeMapsOf(maps), voxel, reach);
    std::map<openvdb::Int32, std::size_t> filled;
    const AccumulatedField accumulated = field.accumulate(voxel);
    for (auto leaf = accumulated.g->tree().cbeginLeaf(); leaf; ++leaf) ++filled[leaf->origin().x()];
    std::size_t total = 0;
    openvdb::Int32 previous = std::numeric_limits<openvdb::Int32>::min();
    for (const auto& [x, leaves] : columns) {
      EXPECT_EQ(x % 8, 0) << voxel;
      EXPECT_GT(x, previous) << "in order of x";
      previous = x;
      EXPECT_GE(leaves, filled[x]) << "column " << x << ", voxel " << voxel;
      EXPECT_GT(leaves, 0u);
      total += leaves;
    }
    EXPECT_EQ(filled.size(), columns.size()) << "a column that no leaf is filled in, or a filled one left out";
    EXPECT_LE(static_cast<double>(total), accumulationCost(maps, voxel, reach).leaves) << voxel;
    EXPECT_LT(static_cast<double>(total), 3.0 * static_cast<double>(accumulated.g->tree().leafCount())) << voxel;
  }
}

TEST(AccumulationCost, AMapsSpanIsTheColumnsOfTheLeavesItsWindowsFill) {
  // Accumulated alone, each map fills leaves in the columns of its span, the
  // first and the last among them (the views along x see one half of the
  // sphere each, across x = 0 from either side).
  const std::vector<RangeMap> maps = sphereViews();
  const double voxel = 0.05;
  openvdb::Int32 lowest = 0, highest = 0;
  for (const RangeMap& map : maps) {
    const ForceField field(std::vector<RangeMap>{map}, defaultForceFieldOptions(maps, voxel));
    ReachedLeaves reached(voxel, field.options().dataWindow().reach());
    const ReachedLeaves::Span span = reached.add(map);
    ASSERT_FALSE(span.empty()) << map.name();
    openvdb::Int32 first = std::numeric_limits<openvdb::Int32>::max(), last = std::numeric_limits<openvdb::Int32>::min();
    const AccumulatedField accumulated = field.accumulate(voxel);
    for (auto leaf = accumulated.g->tree().cbeginLeaf(); leaf; ++leaf) {
      first = std::min(first, leaf->origin().x());
      last = std::max(last, leaf->origin().x());
    }
    EXPECT_LE(span.first, first) << map.name();
    EXPECT_GE(span.last, last) << map.name();
    const std::vector<openvdb::Coord> marked = detail::leavesReached(map, voxel, field.options().dataWindow().reach());
    const auto [leftmost, rightmost] = std::minmax_element(
        marked.begin(), marked.end(), [](const openvdb::Coord& a, const openvdb::Coord& b) { return a.x() < b.x(); });
    EXPECT_EQ(span.first, leftmost->x()) << map.name() << ": the first column of the leaves its windows reach";
    EXPECT_EQ(span.last, rightmost->x()) << map.name() << ": the last";
    lowest = std::min(lowest, span.first);
    highest = std::max(highest, span.last);
  }
  EXPECT_LT(lowest, -8);
  EXPECT_GT(highest, 8);
  EXPECT_TRUE(ReachedLeaves(voxel, 0.1).add(RangeMap::orthographic(2, 2, std::vector<float>(4, NAN),
                                                                    OrthographicProjection{0.1, {0.0, 0.0}},
                                                                    openvdb::math::Mat4d::identity(), 0.01, "none"))
                  .empty())
      << "a map without readings reaches no leaf";
}

}  // namespace
}  // namespace levelfuse
