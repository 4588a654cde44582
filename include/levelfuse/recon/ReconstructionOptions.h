// levelfuse: the settings of a reconstruction and their resolution from the
// scans: every setting left unset is derived from what the scans tell, once,
// in one place.
#pragma once

#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/recon/FusionSettings.h>
#include <levelfuse/scan/DataWindow.h>
#include <levelfuse/scan/ScanSummary.h>

#include <cstddef>
#include <optional>
#include <string>

namespace levelfuse {

/// Where the evolution takes its data term from.
enum class DataTermSource {
  kAuto,    ///< grids from more than kGridsFromScans range maps, per map below
  kPerMap,  ///< every range map that reaches an active voxel, at every iteration (ForceField)
  kGrids,   ///< grids accumulated once per grid level, binned by line of sight (DataTermGrids)
};

/// From how many range maps kAuto samples the data term from grids: below,
/// evaluating each map where the surface is costs less time and memory than
/// grids (docs/RECONSTRUCTION.md has the measurements).
inline constexpr std::size_t kGridsFromScans = 32;

/// The settings a reconstruction takes as they are given: none is derived
/// from the scans. ReconstructionOptions adds those that may be left to the
/// data; ReconstructionSettings holds them all, resolved.
struct ReconstructionControls {
  WindowKind window = WindowKind::kGaussian;
  /// A grid has converged when the rms speed of its active values falls below
  /// this many voxels per unit time (the data term relaxes in about one). Values
  /// the speed leaves at rest (no reading reaches them and the prior is off) are
  /// not counted: the surface no scan saw is not waited for.
  double tolerance = 0.05;
  /// A grid has also settled when its rms speed has not fallen (by 5%) for
  /// `patience` iterations and no region the scans saw drifts by `drift`
  /// voxels per iteration or more (the mean change over a leaf node's active
  /// voxels, measured over `patience` iterations): points whose zero crossing lies
  /// near the edge of their voxel keep trading places with their neighbours,
  /// and noisy data keep the surface trembling, so the speed of a settled
  /// surface does not fall to zero, while a region still on its way moves
  /// steadily one way.
  int patience = 8;
  double drift = 0.025;
  int minIterations = 4;    ///< per grid
  int maxIterations = 300;  ///< per grid
  std::string name = "surface";  ///< the output grid's name
  /// On a team (run with a SlabTeam), each process keeps its slab's piece of
  /// the output, the whole level set there (levelset/LevelSetPieces.h,
  /// closeLevelSetPiece), with the weight and colour grids of that piece,
  /// and no process assembles the whole: for pipelines that keep the pieces
  /// apart, and for outputs larger than one process's memory. The pieces'
  /// CSG union is the assembled level set.
  bool keepPieces = false;
  SparseFieldOptions engine;     ///< the sparse-field engine's settings
  /// The memory the reconstruction may use: each stage estimates what it
  /// needs before it allocates and throws InsufficientMemory, saying what
  /// would fit, where it would not. By default the machine's physical memory
  /// or the process's limit.
  MemoryBudget memoryBudget;
};

/// Settings of a reconstruction as asked for. The four left empty by default
/// are derived from the data (resolveReconstructionSettings).
struct ReconstructionOptions : ReconstructionControls {
  /// Voxel size of the finest grid (world units). Derived: the scans' median
  /// distance between neighbouring rays, the resolution the data supports.
  std::optional<double> voxelSize;
  /// Number of grids, each with half the voxel size of the one before.
  /// Derived: so many that the coarsest grid is about 64 voxels across the
  /// data; one for depth frames (pinhole range maps), whose many views give
  /// the finest grid's linear solution every surface a coarse grid would lose.
  std::optional<int> levels;
  /// Weight of the surface-area prior (Eq. 19), in voxels of the finest grid:
  /// where the data support a surface, a sphere of radius R voxels settles
  /// 2 beta / R voxels inside it. 0 turns the prior off. Derived:
  /// max(0.5, sigma / voxel size) with sigma the scans' median noise, the
  /// best weight measured on noisy synthetic scans (docs/RESULTS.md); 0 for
  /// depth frames, where it was measured to round edges and retract surfaces
  /// seen from one side only, and held-out frames fit best without it.
  std::optional<double> beta;
  /// Width of the data term's window (Eqs. 8-9), world units. Derived: the
  /// scans' median noise sigma: a reading speaks for the space within its own
  /// uncertainty, and scans of thin walls seen from both sides do not
  /// interfere (measured on the noisy mug, docs/RESULTS.md). The window never
  /// narrows below a voxel of the grid it works on.
  std::optional<double> epsilon;
  /// Where the evolution samples the data term; kAuto is resolved to one of the others.
  DataTermSource dataTerm = DataTermSource::kAuto;
};

/// Every setting of a reconstruction, resolved from the options and the
/// scans (resolveReconstructionSettings): what a Reconstructor runs with.
/// The fields are those of ReconstructionOptions, each set.
struct ReconstructionSettings : ReconstructionControls {
  double voxelSize = 0.0;  ///< of the finest grid (world units)
  int levels = 1;          ///< grids, each with half the voxel size of the one before
  double beta = 0.0;       ///< the prior's weight in voxels of the finest grid (Eq. 19)
  double epsilon = 0.0;    ///< the window's width (world units; Eqs. 8-9)
  DataTermSource dataTerm = DataTermSource::kPerMap;  ///< kPerMap or kGrids, never kAuto
};

/// The smallest voxel size a grid can have: OpenVDB's transforms refuse a
/// scale whose cube is below 3e-15 (math::Tolerance<double>), so 1.5e-5
/// world units, 15 micrometres for scans in metres.
inline constexpr double kSmallestVoxelSize = 1.5e-5;

/// The settings of a reconstruction from the options `given` and the
/// summary of its scans: every setting left unset derived, every one checked.
/// Throws std::invalid_argument for no readings or unusable options, with a
/// hint. Resolved once per run: a Reconstructor, a Fusion of scans read one at
/// a time (fusionSettingsOf) and a team that reads its scans in parts
/// (readTeamScans) each take the same settings.
ReconstructionSettings resolveReconstructionSettings(const ReconstructionOptions& given, const ScanSummary& scans);
/// The settings as options with every setting given: resolving them again
/// gives them back.
ReconstructionOptions optionsOf(const ReconstructionSettings& settings);
/// The grids of resolved settings, as a Fusion takes them.
FusionSettings fusionSettingsOf(const ReconstructionSettings& settings);

}  // namespace levelfuse
