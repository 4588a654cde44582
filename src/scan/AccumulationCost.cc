// levelfuse: what accumulating the data term on a grid costs.

#include <levelfuse/scan/AccumulationCost.h>

#include "LeavesReached.h"

#include <algorithm>
#include <cmath>

namespace levelfuse {

AccumulationCost accumulationCost(const std::vector<RangeMap>& maps, double voxelSize, double reach) {
  return accumulationCost(rangeMapsOf(maps), voxelSize, reach);
}

AccumulationCost accumulationCost(const RangeMapSequence& maps, double voxelSize, double reach) {
  AccumulationCost cost;
  openvdb::BBoxd reached;
  maps([&](const RangeMap& m) { cost.leafMarks += detail::leafMarks(m, voxelSize, reach, reached); });
  if (std::isnan(cost.leafMarks)) cost.leafMarks = HUGE_VAL;  // boxes that reach infinity
  double boxLeaves = 0.0;
  if (cost.leafMarks > 0.0) {
    boxLeaves = 1.0;
    for (int axis = 0; axis < 3; ++axis) boxLeaves *= std::floor(reached.extents()[axis] / (8.0 * voxelSize)) + 2.0;
  }
  cost.leaves = std::isnan(boxLeaves) ? cost.leafMarks : std::min(cost.leafMarks, boxLeaves);
  cost.bytes = kBytesPerLeafMark * cost.leafMarks + kBytesPerAccumulatedLeaf * cost.leaves;
  return cost;
}

}  // namespace levelfuse
