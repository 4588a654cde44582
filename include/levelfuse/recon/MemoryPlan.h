// levelfuse: the memory a reconstruction will need, estimated before it
// allocates, against the settings' memory budget (core/MemoryBudget.h): every estimate
// and its check, each saying what would fit when it does not.
#pragma once

#include <levelfuse/recon/ReconstructionOptions.h>
#include <levelfuse/scan/AccumulationCost.h>

#include <openvdb/openvdb.h>

#include <cstddef>
#include <stdexcept>
#include <string>

namespace levelfuse {

class SlabTeam;

/// Thrown when a stage would need more memory than the settings' memory
/// budget (ReconstructionControls::memoryBudget), before it allocates; the
/// message says what would fit.
class InsufficientMemory : public std::runtime_error {
 public:
  explicit InsufficientMemory(const std::string& what) : std::runtime_error(what) {}
};

/// Memory a reconstruction needs at its peak per voxel of the finest grid's
/// active set (|psi| <= dx / 2): the sparse field and its layers (about 110
/// bytes), the data term accumulated around the readings, the level set it is
/// refined from and the snapshot that measures drift: what the bunny needed
/// across voxel sizes (docs/RELIABILITY.md, "Memory guards").
inline constexpr double kPeakBytesPerActiveVoxel = 450.0;
/// The same for one process of a team of n that shares the evolution
/// (Reconstructor::run with a SlabTeam): its slab of every grid, a share of
/// kPeakBytesPerActiveVoxel / n with a margin for cuts at whole columns of
/// leaf nodes (kSlabShareMargin), and at the first process, once its slab
/// has gone, the whole output (kOutputBytesPerActiveVoxel): the level set,
/// half-width 3, and beside it its weight grid or what the converter measures
/// and meshes it with, each of the surface's size: what the converter's first
/// process needed with a mesh (docs/RELIABILITY.md, "Memory guards").
inline constexpr double kSlabShareMargin = 1.15;
inline constexpr double kOutputBytesPerActiveVoxel = 300.0;

/// Throws InsufficientMemory if accumulating the data term of the maps whose
/// cost `costOf` finds on grid `level` of the settings would not fit,
/// saying which voxel size would: asked before integrating
/// (Reconstructor::run, and whoever fuses maps read one at a time).
void requireAccumulationMemory(const AccumulationCostOf& costOf, const ReconstructionSettings& settings, int level);
/// Throws InsufficientMemory if the coarsest grid of the settings
/// cannot classify every leaf-sized block of the data's box `bounds` (the
/// linear solution's first pass).
void requireCoarsestGridMemory(const ReconstructionSettings& settings, const openvdb::BBoxd& bounds);
/// Throws InsufficientMemory if the finest grid of a surface with this many
/// active voxels on the coarsest grid would not fit: the whole of it, or
/// this process's share on a `team`.
void requireFinestGridMemory(const ReconstructionSettings& settings, std::size_t coarsestActiveVoxels,
                             const SlabTeam* team = nullptr);

}  // namespace levelfuse
