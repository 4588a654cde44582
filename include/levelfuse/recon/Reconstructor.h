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

/// Settings of a reconstruction. The four left empty by default are derived
/// from the data; Reconstructor::options() reports them all set.
struct ReconstructionOptions {
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
  WindowKind window = WindowKind::kGaussian;
  /// Where the evolution samples the data term; kAuto is resolved to one of the others.
  DataTermSource dataTerm = DataTermSource::kAuto;
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
};

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

/// Thrown by Reconstructor::run when the finest grid would need more memory
/// than io::memoryBudget() (the machine's physical memory or the process's
/// limit, or what io::setMemoryBudget() set); run() estimates it from the
/// initial model before it allocates, and the message says which voxel size
/// would fit.
class InsufficientMemory : public std::runtime_error {
 public:
  explicit InsufficientMemory(const std::string& what) : std::runtime_error(what) {}
};

/// The smallest voxel size a grid can have: OpenVDB's transforms refuse a
/// scale whose cube is below 3e-15 (math::Tolerance<double>), so 1.5e-5
/// world units, 15 micrometres for scans in metres.
inline constexpr double kSmallestVoxelSize = 1.5e-5;

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

/// `given` with every derived setting resolved from the scans' summary as
/// Reconstructor does (its options()): a fusion of scans read one at a time
/// takes its settings from it (fusionSettingsOf). Throws
/// std::invalid_argument for no readings or unusable options, with a hint.
ReconstructionOptions resolveReconstructionOptions(const ReconstructionOptions& given, const ScanSummary& scans);
/// The grids of resolved options (resolveReconstructionOptions), as a Fusion takes them.
FusionSettings fusionSettingsOf(const ReconstructionOptions& resolved);
/// Throws InsufficientMemory if accumulating the data term of the maps whose
/// cost `costOf` finds on grid `level` of the resolved options would not fit,
/// saying which voxel size would: asked before integrating
/// (Reconstructor::run, and whoever fuses maps read one at a time).
void requireAccumulationMemory(const AccumulationCostOf& costOf, const ReconstructionOptions& resolved, int level);

class Fusion;
class SlabTeam;
namespace detail {
class EvolvingField;
}

class Reconstructor {
 public:
  /// Resolves the options' defaults from the data; throws std::invalid_argument
  /// for no range maps or unusable options, with a hint. When the data term
  /// comes from grids, run() integrates the maps into a Fusion of every grid
  /// level at once.
  Reconstructor(std::vector<RangeMap> maps, const ReconstructionOptions& options = {});
  /// Reconstructs from the maps `fusion` integrated (the fusion must outlive
  /// the reconstructor): the derived settings come from the fusion's summary
  /// of its maps, the voxel size, levels, window and epsilon are the
  /// fusion's (given ones must agree), and the data term is its grids.
  /// Throws std::invalid_argument before any map, for settings that disagree
  /// with the fusion's, or for a data term from the maps (kPerMap).
  explicit Reconstructor(const Fusion& fusion, const ReconstructionOptions& options = {});

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

  /// The options with every derived setting resolved (all four set).
  const ReconstructionOptions& options() const { return mOptions; }
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
  /// Throws InsufficientMemory if the coarsest grid's box would not fit.
  void requireCoarsestGridMemory() const;
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
  /// Throws InsufficientMemory if accumulating the data term on grid `level`
  /// would not fit (accumulationCost), saying which voxel size would.
  void requireAccumulationMemory(int level) const;
  /// Throws InsufficientMemory if the finest grid of a surface with this many
  /// active voxels on the coarsest grid would not fit: the whole of it, or
  /// this process's share on a `team`.
  void requireFinestGridMemory(std::size_t coarsestActiveVoxels, const SlabTeam* team = nullptr) const;

  std::shared_ptr<const std::vector<RangeMap>> mMaps;
  const Fusion* mFusion = nullptr;  ///< the data term's source, if it was built on one
  ReconstructionOptions mOptions;
  ScanSummary mSummary;
};

}  // namespace levelfuse
