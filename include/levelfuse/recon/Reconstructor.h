// levelfuse: surfaces from range maps, the pipeline of section 6 of the paper.
//
//  1. The linear solution (the zero set of g, Eq. 17) on a coarse grid is the
//     initial model (from that grid's data term when the evolution samples
//     grids: the scans are integrated once for both).
//  2. A sparse field evolves it under the facing-checked data term sampled at
//     subcell positions plus the surface-area prior (DataSpeed.h) until the
//     change per iteration falls below a threshold.
//  3. The result is resampled to half the voxel size and evolved again, down
//     to the requested voxel size: a continuation from coarse to fine.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/core/PhaseClock.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/recon/FusionSettings.h>
#include <levelfuse/recon/MemoryPlan.h>
#include <levelfuse/recon/ReconstructionOptions.h>
#include <levelfuse/scan/AccumulationCost.h>
#include <levelfuse/scan/DataTermGrids.h>
#include <levelfuse/scan/ForceField.h>
#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/scan/ScanSummary.h>

#include <openvdb/openvdb.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace levelfuse {


/// Where a reconstruction is; passed to the progress callback.
struct ReconstructionProgress {
  enum class Stage { kInitialModel, kIntegrating, kEvolving, kResampling, kDone };
  Stage stage = Stage::kInitialModel;
  /// kIntegrating: the scans integrated so far, into every grid at once;
  /// kInitialModel: the scans space carving has asked so far in its round (it
  /// asks them all twice: for the blocks around the data, then for the voxels
  /// of the carved surface).
  std::size_t scan = 0;
  std::size_t scans = 0;   ///< the scans to integrate
  int level = 0;           ///< 0 is the coarsest grid
  int levels = 0;
  double voxelSize = 0.0;
  int iteration = 0;       ///< within the grid
  int maxIterations = 0;
  std::size_t activeSetVoxels = 0;  ///< the active set L0 (|psi| <= half a voxel), not the whole band
  double speed = 0.0;      ///< rms speed of the active values not at rest in the last iteration (voxels per unit time)
  double drift = 0.0;      ///< the largest local drift last measured (voxels per iteration)
  double seconds = 0.0;    ///< since the start
};

/// Called between iterations; return false to cancel the reconstruction.
using ProgressCallback = std::function<bool(const ReconstructionProgress&)>;

/// Thrown by Reconstructor::run when the progress callback asks to stop.
class ReconstructionCancelled : public Interrupted {
 public:
  ReconstructionCancelled() : Interrupted("the reconstruction was cancelled") {}
};


/// What one grid of the reconstruction did.
struct LevelReport {
  double voxelSize = 0.0;
  int iterations = 0;
  bool converged = false;  ///< its speed fell below the tolerance
  bool settled = false;    ///< its speed stopped falling
  double simulatedTime = 0.0;
  double seconds = 0.0;
  std::size_t activeSetVoxels = 0;  ///< the active set L0 at the end of the grid
  std::size_t bandVoxels = 0;       ///< every layer, L0 included: the narrow band
  std::size_t engineBytes = 0;  ///< the sparse field's memory at the end of the grid (this process's)
  /// Leaf nodes of the field at the end of the grid: on a team (run with a
  /// SlabTeam), this process's slab's own.
  std::size_t ownLeafNodes = 0;
  /// The grid's data term that this process integrated for it alone, within
  /// its slab (a team's deferred finer grid, Fusion::deferLevel); 0 for
  /// grids whose data term came ready.
  std::size_t slabDataTermBytes = 0;
};

struct ReconstructionResult {
  /// A standard OpenVDB level set: GRID_LEVEL_SET, half-width 3, named as the
  /// options say, with the parameters in its metadata (levelfuse_*).
  openvdb::FloatGrid::Ptr levelSet;
  /// The readings that face the level set on its narrow band
  /// (recon/SurfaceWeight.h): GRID_UNKNOWN, named "weight", the level set's
  /// transform, its active voxels in the leaves some reading faces; 0 where
  /// no scan observed the surface.
  openvdb::FloatGrid::Ptr weight;
  /// The colour the scans saw on the level set's narrow band
  /// (scan/SurfaceColour.h): a Vec3fGrid named "Cd"; null when no scan
  /// carries colour.
  openvdb::Vec3fGrid::Ptr colour;
  std::vector<LevelReport> levels;
  double seconds = 0.0;
  /// Where the time went: "integrating" (when run() fuses the scans itself),
  /// "linear solution" (space carving and the initial model, Eq. 17),
  /// "evolution", "resampling", "surface weight", "colour".
  std::vector<PhaseTime> phases;
  std::size_t peakEngineBytes = 0;  ///< the largest sparse field along the way
};


class Fusion;
class SlabTeam;
namespace detail {
class EvolvingField;
}

class Reconstructor {
 public:
  /// Resolves the options' defaults from the data
  /// (resolveReconstructionSettings); throws std::invalid_argument for no
  /// range maps or unusable options, with a hint. When the data term comes
  /// from grids, run() integrates the maps into a Fusion of every grid level
  /// at once.
  Reconstructor(std::vector<RangeMap> maps, const ReconstructionOptions& options = {});
  /// Runs with `settings` resolved before (resolveReconstructionSettings), as
  /// a team's processes do with the settings of all their scans
  /// (readTeamScans). Throws std::invalid_argument for no range maps.
  Reconstructor(std::vector<RangeMap> maps, const ReconstructionSettings& settings);
  /// Reconstructs from the maps `fusion` integrated (the fusion must outlive
  /// the reconstructor): the derived settings come from the fusion's summary
  /// of its maps, the voxel size, levels, window and epsilon are the
  /// fusion's (given ones must agree), and the data term is its grids.
  /// Throws std::invalid_argument before any map, for settings that disagree
  /// with the fusion's, or for a data term from the maps (kPerMap).
  explicit Reconstructor(const Fusion& fusion, const ReconstructionOptions& options = {});
  /// The same with `settings` resolved before: those the fusion was made
  /// with (fusionSettingsOf), or std::invalid_argument.
  Reconstructor(const Fusion& fusion, const ReconstructionSettings& settings);

  /// Runs the pipeline. Throws ReconstructionCancelled if `progress` returns
  /// false, Interrupted if `interrupter` stops the initial model (the linear
  /// solution, before the first progress report), InsufficientMemory if the
  /// finest grid would not fit.
  ///
  /// With a `team` of more than one process (levelset/SlabTeam.h, e.g. the
  /// ranks of an MPI job, mpi/RankTeam.h), every process runs it alike on
  /// the same scans and options; each evolves one slab of every grid, cut
  /// along x where the coarsest grid's leaf nodes share out evenly. The
  /// result is one process's, bit for bit, and only the team's first process
  /// holds it (the level set, weight and colour are null on the others), or,
  /// with options keepPieces, every process holds its piece of it. The
  /// scans are every process's whole. So are the data term and the initial
  /// model, but in a run of one grid from grids of the data term (depth
  /// frames): there each process integrates the maps within its slab of the
  /// data alone (recon/SharedData.h), and makes its slab of the initial model
  /// from that part.
  ReconstructionResult run(const ProgressCallback& progress = {}, const Interrupter& interrupter = {},
                           const SlabTeam* team = nullptr) const;

  /// The linear solution (the zero set of g, Eq. 17) on the finest grid
  /// alone, no evolution: VRIP-style fusion. Throws InsufficientMemory, as
  /// run() does, if the finest grid would not fit; Interrupted if
  /// `interrupter` stops it.
  openvdb::FloatGrid::Ptr linearSolution(const Interrupter& interrupter = {}) const;
  /// The data weight on `levelSet`'s narrow band from the finest grid's data
  /// term (recon/SurfaceWeight.h), as run() returns it with its surface: for a
  /// linear solution, or a surface edited since. Interrupted if `interrupter`
  /// stops it.
  openvdb::FloatGrid::Ptr surfaceWeight(const openvdb::FloatGrid& levelSet, const Interrupter& interrupter = {}) const;

  /// The colour the scans saw on `levelSet`'s narrow band
  /// (scan/SurfaceColour.h), as run() returns it with its surface; null when
  /// no scan carries colour (or a fusion's maps were not kept). Interrupted if
  /// `interrupter` stops it.
  openvdb::Vec3fGrid::Ptr surfaceColour(const openvdb::FloatGrid& levelSet, const Interrupter& interrupter = {}) const;

  /// Every setting, resolved.
  const ReconstructionSettings& settings() const { return mSettings; }
  /// Voxel size of grid `level` (0 is the coarsest).
  double voxelSize(int level) const;
  /// The data term's settings on grid `level`.
  ForceFieldOptions forceOptions(int level) const;
  /// The data term of every scan accumulated on grid `level`; throws
  /// Interrupted between scans if `interrupter` asks to stop. `integrated`,
  /// if set, is told after each scan how many are in. Throws
  /// std::invalid_argument for a reconstructor of a fusion (Fusion::dataTerm).
  DataTermGrids dataTermGrids(int level, const Interrupter& interrupter = {},
                              const std::function<void(std::size_t)>& integrated = {}) const;
  /// The range maps (none for a reconstructor of a fusion: it keeps them).
  const std::vector<RangeMap>& maps() const { return *mMaps; }
  /// What the derived settings were taken from.
  const ScanSummary& summary() const { return mSummary; }
  /// World box of the scans' readings.
  const openvdb::BBoxd& bounds() const { return mSummary.bounds(); }

 private:
  /// Throws InsufficientMemory if accumulating this reconstructor's maps on
  /// grid `level` would not fit (requireAccumulationMemory).
  void requireMapsAccumulationMemory(int level) const;
  /// The maps integrated into a fusion of every grid level (progress reported scan by scan).
  /// On a `team` that shares the data in slabs (recon/SharedData.h), the
  /// fusion holds this process's slab of the data alone.
  std::unique_ptr<Fusion> fuseScans(ReconstructionProgress& state, const std::function<void()>& report,
                                    const Interrupter& interrupter, const SlabTeam* team) const;
  /// The linear solution on the coarsest grid, as a sparse field: from the
  /// fusion's coarsest grid if it is given, else accumulated from the scans.
  /// `carvedWith`, if set, is told after each scan carving asks how many it
  /// has asked in the round (carving asks them all twice).
  SparseField initialModel(const Interrupter& interrupter, const Fusion* fusion = nullptr,
                           const std::function<void(std::size_t)>& carvedWith = {}) const;
  /// The same, this process's slab of it, from a fusion of this process's slab
  /// of the data (Fusion::dataSlab): `team` agrees on the whole data's box.
  SlabField initialSlab(const Interrupter& interrupter, const Fusion& fusion,
                        const std::function<void(std::size_t)>& carvedWith, const SlabTeam& team) const;
  /// How the initial model's narrow band is made: rebuilt on a coarse grid.
  LinearBand initialBand() const;
  /// The maps that carving asks, `carvedWith` told after each how many it has asked.
  RangeMapSequence carvingScans(const std::function<void(std::size_t)>& carvedWith) const;
  /// Throws std::invalid_argument, naming `what`, if the fusion holds one slab of the data alone.
  void requireWholeData(const char* what) const;
  /// Evolves `field`, of voxel size h, under the data term and the prior
  /// until it converges, settles or reaches the iteration limit (section 6).
  template <typename Field>
  LevelReport evolveLevel(detail::EvolvingField& field, const Field& data, double h, ReconstructionProgress& state,
                          const std::function<void()>& report) const;
  /// Grid `level` of run(): `field` resampled from the grid before (if any)
  /// and evolved; on the finest grid, the result's level set and weight.
  /// The data term is the fusion's grids if it is given (a deferred grid's
  /// integrated within this process's slab, dataTermOfSlab), else the maps'.
  LevelReport reconstructLevel(int level, detail::EvolvingField& field, const Fusion* fusion,
                               ReconstructionProgress& state, const std::function<void()>& report,
                               const Interrupter& interrupter, ReconstructionResult& result, PhaseClock& clock) const;
  /// The data term of the fusion's deferred grid `level` (Fusion::deferLevel)
  /// within this process's slab of `field` and the data it reads beyond
  /// (dataSlabOf), once its memory is found to fit (InsufficientMemory if not).
  std::unique_ptr<DataTermGrids> dataTermOfSlab(int level, const detail::EvolvingField& field, const Fusion& fusion,
                                                ReconstructionProgress& state, const std::function<void()>& report,
                                                const Interrupter& interrupter) const;
  /// The run's parameters as the output grid's levelfuse_* metadata.
  void describeRun(openvdb::FloatGrid& out, int iterations) const;

  std::shared_ptr<const std::vector<RangeMap>> mMaps;
  const Fusion* mFusion = nullptr;  ///< the data term's source, if it was built on one
  ReconstructionSettings mSettings;
  ScanSummary mSummary;
};

/// The MAP reconstruction from the maps `fusion` has integrated so far
/// (Reconstructor on the fusion): `options`' voxel size, levels, window and
/// epsilon must be left empty or agree with the fusion's settings.
ReconstructionResult reconstruct(const Fusion& fusion, const ReconstructionOptions& options = {},
                                 const ProgressCallback& progress = {}, const Interrupter& interrupter = {});

}  // namespace levelfuse
