// levelfuse: what accumulating the data term on a grid costs.

#include <levelfuse/scan/AccumulationCost.h>

#include <levelfuse/core/Parallel.h>
#include <levelfuse/scan/PackedRangeMap.h>

#include "LeavesReached.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace levelfuse {

AccumulationCost accumulationCost(const std::vector<RangeMap>& maps, double voxelSize, double reach) {
  return accumulationCost(rangeMapsOf(maps), voxelSize, reach);
}

namespace {

/// The cost of leaf marks over maps whose windows reach the box `reached`.
AccumulationCost costOfMarks(double leafMarks, const openvdb::BBoxd& reached, double voxelSize) {
  AccumulationCost cost;
  cost.leafMarks = std::isnan(leafMarks) ? HUGE_VAL : leafMarks;  // boxes that reach infinity
  double boxLeaves = 0.0;
  if (cost.leafMarks > 0.0) {
    boxLeaves = 1.0;
    for (int axis = 0; axis < 3; ++axis) boxLeaves *= std::floor(reached.extents()[axis] / (8.0 * voxelSize)) + 2.0;
  }
  cost.leaves = std::isnan(boxLeaves) ? cost.leafMarks : std::min(cost.leafMarks, boxLeaves);
  cost.bytes = kBytesPerLeafMark * cost.leafMarks + kBytesPerAccumulatedLeaf * cost.leaves;
  return cost;
}

}  // namespace

AccumulationCost accumulationCost(const RangeMapSequence& maps, double voxelSize, double reach, double xMin,
                                  double xMax) {
  double leafMarks = 0.0;
  openvdb::BBoxd reached;
  maps([&](const RangeMap& m) { leafMarks += detail::leafMarks(m, voxelSize, reach, reached, xMin, xMax); });
  return costOfMarks(leafMarks, reached, voxelSize);
}

ReachedLeaves::Span ReachedLeaves::add(const RangeMap& map) {
  Span span;
  openvdb::tree::ValueAccessor<openvdb::MaskTree> leaves(mLeaves);
  for (const openvdb::Coord& origin : detail::leavesReached(map, mVoxelSize, mReach)) {
    leaves.setValueOn(origin >> openvdb::FloatTree::LeafNodeType::LOG2DIM);
    if (span.empty()) span.first = span.last = origin.x();
    span.first = std::min(span.first, origin.x());
    span.last = std::max(span.last, origin.x());
  }
  return span;
}

std::vector<std::pair<openvdb::Int32, std::size_t>> ReachedLeaves::columns() const {
  std::map<openvdb::Int32, std::size_t> perColumn;
  for (auto leaf = mLeaves.cbeginValueOn(); leaf; ++leaf) {
    const openvdb::CoordBBox cells = leaf.getBoundingBox();  // one voxel, or a tile of them
    for (openvdb::Int32 x = cells.min().x(); x <= cells.max().x(); ++x)
      perColumn[x * static_cast<openvdb::Int32>(openvdb::FloatTree::LeafNodeType::DIM)] +=
          static_cast<std::size_t>(cells.dim().y()) * static_cast<std::size_t>(cells.dim().z());
  }
  return {perColumn.begin(), perColumn.end()};
}

openvdb::CoordBBox ReachedLeaves::voxelBox() const {
  openvdb::CoordBBox cells;
  if (!mLeaves.evalActiveVoxelBoundingBox(cells)) return openvdb::CoordBBox();
  constexpr openvdb::Int32 width = openvdb::FloatTree::LeafNodeType::DIM;
  const openvdb::Coord lo = cells.min(), hi = cells.max();
  return openvdb::CoordBBox(lo.x() * width, lo.y() * width, lo.z() * width, hi.x() * width + width - 1,
                            hi.y() * width + width - 1, hi.z() * width + width - 1);
}

std::vector<std::pair<openvdb::Int32, std::size_t>> accumulationColumns(const RangeMapSequence& maps, double voxelSize,
                                                                        double reach) {
  ReachedLeaves reached(voxelSize, reach);
  maps([&](const RangeMap& m) { reached.add(m); });
  return reached.columns();
}

AccumulationCostOf accumulationCostOf(RangeMapSequence maps) {
  return [maps = std::move(maps)](double voxelSize, double reach) { return accumulationCost(maps, voxelSize, reach); };
}

AccumulationCostWithin accumulationCostWithin(RangeMapSequence maps) {
  return [maps = std::move(maps)](double voxelSize, double reach, double xMin, double xMax) {
    return accumulationCost(maps, voxelSize, reach, xMin, xMax);
  };
}

AccumulationCostWithin accumulationCostWithin(const PackedScans& scans) {
  return [&scans](double voxelSize, double reach, double xMin, double xMax) {
    const std::size_t count = scans.maps.size();
    std::vector<double> marks(count, 0.0);
    std::vector<openvdb::BBoxd> boxes(count);
    parallelFor(count, 1, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        marks[i] = detail::leafMarks(scans.maps[i].unpack(), voxelSize, reach, boxes[i], xMin, xMax);
    });
    // Summed in the maps' order, as accumulationCost visits them.
    double leafMarks = 0.0;
    openvdb::BBoxd reached;
    for (std::size_t i = 0; i < count; ++i) {
      leafMarks += marks[i];
      reached.expand(boxes[i]);
    }
    return costOfMarks(leafMarks, reached, voxelSize);
  };
}

AccumulationCostOf overAllOfX(AccumulationCostWithin costWithin) {
  return [costWithin = std::move(costWithin)](double voxelSize, double reach) {
    return costWithin(voxelSize, reach, -HUGE_VAL, HUGE_VAL);
  };
}

AccumulationCostOf accumulationCostOf(const PackedScans& scans) { return overAllOfX(accumulationCostWithin(scans)); }

}  // namespace levelfuse
