// What accumulating the data term costs, known before it is done.

#include <levelfuse/scan/AccumulationCost.h>
#include <levelfuse/scan/ForceField.h>
#include <levelfuse/scan/PackedRangeMap.h>
#include <levelfuse/scan/Synth.h>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

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

}  // namespace
}  // namespace levelfuse
