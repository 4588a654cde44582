// levelfuse: the memory a reconstruction will need, checked before it allocates.

#include "ShortNumber.h"

#include <levelfuse/io/MemoryBudget.h>
#include <levelfuse/levelset/SlabTeam.h>
#include <levelfuse/recon/MemoryPlan.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace levelfuse {

using detail::shortNumber;

namespace {

/// Throws InsufficientMemory if `bytes` exceed the memory budget (io::memoryShortfall).
void requireMemory(double bytes, const std::string& what, const std::string& advice) {
  const std::string shortfall = io::memoryShortfall(bytes, what, advice);
  if (!shortfall.empty()) throw InsufficientMemory("reconstruction: " + shortfall);
}

}  // namespace

void requireCoarsestGridMemory(const ReconstructionOptions& resolved, const openvdb::BBoxd& bounds) {
  // The linear solution classifies every leaf-sized block of the data's box.
  const double h = fusionSettingsOf(resolved).levelVoxelSize(0);
  double blocks = 1.0;
  for (int axis = 0; axis < 3; ++axis) blocks *= bounds.extents()[axis] / (8.0 * h) + 3.0;
  requireMemory(16.0 * blocks, "the initial model on a grid of voxel size " + shortNumber(h),
                "use more grids (levels) or a larger voxel size");
}

void requireAccumulationMemory(const AccumulationCostOf& costOf, const ReconstructionOptions& resolved, int level) {
  const FusionSettings grids = fusionSettingsOf(resolved);
  const auto costAt = [&](double finest) {
    const double h = std::ldexp(finest, grids.levels - 1 - level);
    return costOf(h, forceFieldOptions(grids.epsilon, h, grids.window).dataWindow().reach());
  };
  const AccumulationCost cost = costAt(grids.voxelSize);
  const double budget = static_cast<double>(io::memoryBudget());
  if (cost.bytes <= budget) return;
  // What would fit: the finest voxel size doubled until the data term's leaves do (a window of
  // a fixed width reaches fewer, larger leaves), if some size within a million times does.
  std::string advice = "no voxel size up to a million times this one fits: check the scans' geometry (focal "
                       "lengths, depth scale, pixel size) and the window width epsilon";
  for (double finest = 2.0 * grids.voxelSize; finest <= 1e6 * grids.voxelSize; finest *= 2.0)
    if (costAt(finest).bytes <= 0.9 * budget) {
      advice = "choose a voxel size of at least " + shortNumber(finest) +
               " or a narrower window width epsilon";
      break;
    }
  requireMemory(cost.bytes,
                "the data term on a grid of voxel size " + shortNumber(grids.levelVoxelSize(level)) +
                    " (windows reaching " + shortNumber(grids.levelForceOptions(level).dataWindow().reach()) +
                    " from their readings, " + shortNumber(cost.leafMarks) + " leaf nodes marked)",
                advice);
}

void requireFinestGridMemory(const ReconstructionOptions& resolved, std::size_t coarsestActiveVoxels,
                             const SlabTeam* team) {
  // The surface's area, and so the active set, grows four times with each grid.
  const double finestActive = static_cast<double>(coarsestActiveVoxels) * std::pow(4.0, *resolved.levels - 1);
  const int processes = team ? team->size() : 1;
  const bool shared = processes > 1;
  // The first process makes the whole output, unless each keeps its piece.
  const bool assembles = shared && team->rank() == 0 && !resolved.keepPieces;
  double perVoxel = kPeakBytesPerActiveVoxel;
  if (shared) perVoxel = kPeakBytesPerActiveVoxel * kSlabShareMargin / processes;
  if (assembles) perVoxel = std::max(perVoxel, kOutputBytesPerActiveVoxel);
  const double bytes = perVoxel * finestActive;
  const double budget = static_cast<double>(io::memoryBudget());
  std::string share;
  if (shared) share = ", this process's share of " + std::to_string(processes);
  if (assembles) share += ", and the whole output";
  requireMemory(bytes,
                "a voxel size of " + shortNumber(*resolved.voxelSize) + " (about " + shortNumber(finestActive / 1e6) +
                    " million voxels on the surface" + share + ")",
                "choose a voxel size of at least " +
                    shortNumber(*resolved.voxelSize * std::sqrt(1.1 * bytes / budget)) + " or allow more memory" +
                    (shared && !assembles ? " or more processes" : ""));
}

}  // namespace levelfuse
