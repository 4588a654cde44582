// levelfuse: the grids of a coarse-to-fine run and the data term's window on
// each, fixed before the first range map is integrated.
#pragma once

#include <levelfuse/scan/DataWindow.h>
#include <levelfuse/scan/ForceField.h>

#include <cstddef>

namespace levelfuse {

struct FusionSettings {
  double voxelSize = 0.0;  ///< the finest grid's voxel size (world units); must be set
  int levels = 1;          ///< grids, each with half the voxel size of the one before (1 to 12)
  /// The window's width (world units; Eqs. 8-9): about the maps' noise sigma
  /// (a depth camera's at the scene's depth). Never narrower than a voxel of
  /// the grid it works on (forceFieldOptions).
  double epsilon = 0.0;
  WindowKind window = WindowKind::kGaussian;
  std::size_t grainSize = 1;  ///< leaf nodes per parallel task; 0 integrates serially
  /// Space carving's votes kept from one linear solution to the next
  /// (CarvingMemo), so that an answer while maps keep coming asks only the new
  /// maps of what the last one asked: about 2 KB per block of voxels asked. A
  /// fusion that answers once, after its last map, need not keep them.
  bool keepCarvingVotes = true;

  /// Voxel size of grid `level` (0 is the coarsest).
  double levelVoxelSize(int level) const;
  /// The data term's settings on grid `level` (forceFieldOptions).
  ForceFieldOptions levelForceOptions(int level) const;
};

}  // namespace levelfuse
