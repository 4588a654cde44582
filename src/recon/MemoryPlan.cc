// levelfuse: the memory a reconstruction will need, checked before it allocates.

#include "ShortNumber.h"

#include <levelfuse/levelset/SlabTeam.h>
#include <levelfuse/recon/MemoryPlan.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace levelfuse {

using detail::shortNumber;

namespace {

/// Throws InsufficientMemory if `bytes` exceed the settings' memory budget.
void requireMemory(const ReconstructionSettings& settings, double bytes, const std::string& what,
                   const std::string& advice) {
  const std::string shortfall = settings.memoryBudget.shortfall(bytes, what, advice);
  if (!shortfall.empty()) throw InsufficientMemory("reconstruction: " + shortfall);
}

}  // namespace

void requireCoarsestGridMemory(const ReconstructionSettings& settings, const openvdb::BBoxd& bounds) {
  // The linear solution classifies every leaf-sized block of the data's box.
  const double h = fusionSettingsOf(settings).levelVoxelSize(0);
  double blocks = 1.0;
  for (int axis = 0; axis < 3; ++axis) blocks *= bounds.extents()[axis] / (8.0 * h) + 3.0;
  requireMemory(settings, 16.0 * blocks, "the initial model on a grid of voxel size " + shortNumber(h),
                "use more grids (levels) or a larger voxel size");
}

void requireAccumulationMemory(const AccumulationCostOf& costOf, const ReconstructionSettings& settings, int level) {
  const FusionSettings grids = fusionSettingsOf(settings);
  const auto costAt = [&](double finest) {
    const double h = std::ldexp(finest, grids.levels - 1 - level);
    return costOf(h, forceFieldOptions(grids.epsilon, h, grids.window).dataWindow().reach());
  };
  const AccumulationCost cost = costAt(grids.voxelSize);
  const double budget = static_cast<double>(settings.memoryBudget.bytes());
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
  requireMemory(settings, cost.bytes,
                "the data term on a grid of voxel size " + shortNumber(grids.levelVoxelSize(level)) +
                    " (windows reaching " + shortNumber(grids.levelForceOptions(level).dataWindow().reach()) +
                    " from their readings, " + shortNumber(cost.leafMarks) + " leaf nodes marked)",
                advice);
}

void requireFinestGridMemory(const ReconstructionSettings& settings, std::size_t coarsestActiveVoxels,
                             const SlabTeam* team) {
  // The surface's area, and so the active set, grows four times with each grid.
  const double finestActive = static_cast<double>(coarsestActiveVoxels) * std::pow(4.0, settings.levels - 1);
  const int processes = team ? team->size() : 1;
  const bool shared = processes > 1;
  // The first process makes the whole output, unless each keeps its piece.
  const bool assembles = shared && team->rank() == 0 && !settings.keepPieces;
  double perVoxel = kPeakBytesPerActiveVoxel;
  if (shared) perVoxel = kPeakBytesPerActiveVoxel * kSlabShareMargin / processes;
  if (assembles) perVoxel = std::max(perVoxel, kOutputBytesPerActiveVoxel);
  const double bytes = perVoxel * finestActive;
  const double budget = static_cast<double>(settings.memoryBudget.bytes());
  std::string share;
  if (shared) share = ", this process's share of " + std::to_string(processes);
  if (assembles) share += ", and the whole output";
  requireMemory(settings, bytes,
                "a voxel size of " + shortNumber(settings.voxelSize) + " (about " + shortNumber(finestActive / 1e6) +
                    " million voxels on the surface" + share + ")",
                "choose a voxel size of at least " +
                    shortNumber(settings.voxelSize * std::sqrt(1.1 * bytes / budget)) + " or allow more memory" +
                    (shared && !assembles ? " or more processes" : ""));
}

}  // namespace levelfuse
