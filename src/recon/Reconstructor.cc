// levelfuse: the reconstruction pipeline (section 6).

#include "EvolvingField.h"

#include <levelfuse/Version.h>
#include <levelfuse/core/FreedMemory.h>
#include <levelfuse/levelset/SlabTeam.h>
#include <levelfuse/recon/DataSpeed.h>
#include <levelfuse/recon/Fusion.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/SharedData.h>
#include <levelfuse/recon/SurfaceWeight.h>
#include <levelfuse/scan/AccumulationCost.h>
#include <levelfuse/scan/SurfaceColour.h>

#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

namespace levelfuse {

namespace {

using Clock = std::chrono::steady_clock;

/// Whether a leaf node counts in the drift: at least eight points of the
/// active set (|psi| <= dx / 2), the first of which the data support (at
/// least one reading's window); `points` receives how many it holds.
template <typename Field>
bool driftCounts(const openvdb::FloatTree::LeafNodeType& leaf, float half, const openvdb::FloatGrid& grid,
                 const Field& data, int& points) {
  points = 0;
  openvdb::Coord first;
  for (auto it = leaf.cbeginValueOn(); it; ++it) {
    if (std::fabs(*it) > half) continue;
    if (points == 0) first = it.getCoord();
    ++points;
  }
  return points >= 8 && data.readings(grid.indexToWorld(first)) >= 1.0;
}

/// The leaf nodes of the field's grid that count in the drift
/// (driftCounts) and that the field answers for (EvolvingField::owns),
/// copied: what the drift is measured from. Surfaces no scan saw (most of a
/// scene's closed level set) move under the prior alone toward a minimal
/// surface, slowly and for long: they are not waited for, nor copied.
template <typename Field>
openvdb::FloatTree::Ptr driftSnapshot(const detail::EvolvingField& field, const Field& data) {
  const openvdb::FloatGrid& now = field.grid();
  const float half = static_cast<float>(0.5 * now.voxelSize()[0]);
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(now.tree());
  std::vector<std::unique_ptr<openvdb::FloatTree::LeafNodeType>> copies(leaves.leafCount());
  leaves.foreach([&](const openvdb::FloatTree::LeafNodeType& leaf, std::size_t i) {
    int points = 0;
    if (field.owns(leaf.origin()) && driftCounts(leaf, half, now, data, points))
      copies[i] = std::make_unique<openvdb::FloatTree::LeafNodeType>(leaf);
  });
  auto snapshot = std::make_shared<openvdb::FloatTree>(now.background());
  for (auto& copy : copies)
    if (copy) snapshot->addLeaf(copy.release());
  return snapshot;
}

/// The largest mean change, over the leaf nodes of the field's grid that
/// count in the drift now and did in `before` (driftSnapshot), of their
/// active set's values since `before` (world units).
template <typename Field>
double largestLocalDrift(const detail::EvolvingField& field, const openvdb::FloatTree& before, const Field& data) {
  const openvdb::FloatGrid& now = field.grid();
  const float half = static_cast<float>(0.5 * now.voxelSize()[0]);
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(now.tree());
  std::vector<double> drift(leaves.leafCount(), 0.0);
  leaves.foreach([&](const openvdb::FloatTree::LeafNodeType& leaf, std::size_t i) {
    const openvdb::FloatTree::LeafNodeType* old = before.probeConstLeaf(leaf.origin());
    int points = 0;
    if (!old || !driftCounts(leaf, half, now, data, points)) return;
    double sum = 0.0;
    for (auto it = leaf.cbeginValueOn(); it; ++it)
      if (std::fabs(*it) <= half) sum += *it - old->getValue(it.pos());
    drift[i] = std::fabs(sum) / points;
  });
  return drift.empty() ? 0.0 : *std::max_element(drift.begin(), drift.end());
}

/// Throws std::invalid_argument for a fusion that holds no range maps yet.
void requireFusedMaps(const Fusion& fusion) {
  if (fusion.scanCount() == 0) throw std::invalid_argument("reconstruction: the fusion holds no range maps yet");
}

/// The settings of a reconstruction from `fusion`'s grids: the voxel size,
/// levels, window and epsilon are the fusion's (given ones must agree), the
/// data term its grids, the rest resolved from `options` and its summary.
ReconstructionSettings settingsOnFusion(const Fusion& fusion, const ReconstructionOptions& options) {
  requireFusedMaps(fusion);
  const FusionSettings& fused = fusion.settings();
  const auto agree = [](const auto& given, const auto& fusions, const char* what) {
    if (given && *given != fusions)
      throw std::invalid_argument(std::string("reconstruction: the ") + what +
                                  " is the fusion's, fixed before its first map: leave it unset");
  };
  agree(options.voxelSize, fused.voxelSize, "voxel size");
  agree(options.levels, fused.levels, "number of grids (levels)");
  agree(options.epsilon, fused.epsilon, "window width epsilon");
  if (options.dataTerm == DataTermSource::kPerMap)
    throw std::invalid_argument("reconstruction: a fusion's data term is its grids (DataTermSource::kGrids)");
  ReconstructionOptions o = options;
  o.voxelSize = fused.voxelSize;
  o.levels = fused.levels;
  o.epsilon = fused.epsilon;
  o.window = fused.window;
  o.dataTerm = DataTermSource::kGrids;
  return resolveReconstructionSettings(o, fusion.summary());
}

/// Throws std::invalid_argument unless `settings` are those of `fusion`'s grids.
void requireFusionSettings(const Fusion& fusion, const ReconstructionSettings& settings) {
  const FusionSettings& fused = fusion.settings();
  if (settings.voxelSize != fused.voxelSize || settings.levels != fused.levels || settings.epsilon != fused.epsilon ||
      settings.window != fused.window || settings.dataTerm != DataTermSource::kGrids)
    throw std::invalid_argument("reconstruction: the settings' grids are not the fusion's: take them from the "
                                "settings the fusion was made with (fusionSettingsOf)");
}

}  // namespace

Reconstructor::Reconstructor(std::vector<RangeMap> maps, const ReconstructionOptions& options)
    : mMaps(std::make_shared<const std::vector<RangeMap>>(std::move(maps))) {
  if (mMaps->empty()) throw std::invalid_argument("reconstruction: no range maps to reconstruct from");
  mSummary = ScanSummary(*mMaps);
  mSettings = resolveReconstructionSettings(options, mSummary);
}

Reconstructor::Reconstructor(std::vector<RangeMap> maps, const ReconstructionSettings& settings)
    : mMaps(std::make_shared<const std::vector<RangeMap>>(std::move(maps))), mSettings(settings) {
  if (mMaps->empty()) throw std::invalid_argument("reconstruction: no range maps to reconstruct from");
  mSummary = ScanSummary(*mMaps);
}

Reconstructor::Reconstructor(const Fusion& fusion, const ReconstructionOptions& options)
    : Reconstructor(fusion, settingsOnFusion(fusion, options)) {}

Reconstructor::Reconstructor(const Fusion& fusion, const ReconstructionSettings& settings)
    : mMaps(std::make_shared<const std::vector<RangeMap>>()), mFusion(&fusion), mSettings(settings),
      mSummary(fusion.summary()) {
  requireFusedMaps(fusion);
  requireFusionSettings(fusion, settings);
}

void Reconstructor::requireMapsAccumulationMemory(int level) const {
  requireAccumulationMemory(accumulationCostOf(rangeMapsOf(*mMaps)), mSettings, level);
}

LinearBand Reconstructor::initialBand() const {
  // Structures thinner than a voxel of a coarse grid are noise against it; the
  // finest grid keeps all it resolves (ForceField.h, LinearBand).
  return mSettings.levels > 1 ? LinearBand::kRebuilt : LinearBand::kZeroCrossings;
}

RangeMapSequence Reconstructor::carvingScans(const std::function<void(std::size_t)>& carvedWith) const {
  // The fusion's own maps, or this reconstructor's.
  RangeMapSequence maps = mFusion ? mFusion->scans() : rangeMapsOf(*mMaps);
  return [maps = std::move(maps), carvedWith](const RangeMapVisitor& visit) {
    std::size_t visited = 0;
    maps([&](const RangeMap& m) {
      visit(m);
      if (carvedWith) carvedWith(++visited);
    });
  };
}

SparseField Reconstructor::initialModel(const Interrupter& interrupter, const Fusion* fusion,
                                        const std::function<void(std::size_t)>& carvedWith) const {
  requireCoarsestGridMemory(mSettings, bounds());
  const LinearBand band = initialBand();
  const RangeMapSequence carving = carvingScans(carvedWith);
  if (fusion) return fusion->linearSolutionField(0, band, mSettings.engine, interrupter, carving);
  requireMapsAccumulationMemory(0);
  const ForceFieldOptions f = forceOptions(0);
  return linearSolutionField(ForceField(mMaps, f).accumulate(voxelSize(0), interrupter), carving,
                             f.dataWindow().reach(), band, mSettings.engine, interrupter);
}

SlabField Reconstructor::initialSlab(const Interrupter& interrupter, const Fusion& fusion,
                                     const std::function<void(std::size_t)>& carvedWith, const SlabTeam& team) const {
  requireCoarsestGridMemory(mSettings, bounds());
  // This process's slab of the data: the team agrees on the whole data's box.
  const SlabBounds data = *fusion.dataSlab();
  const DataTermGrids& grids = fusion.dataTerm(0);
  return linearSolutionSlabField(AccumulatedField{grids.gGrid(), grids.weightGrid(), 0}, carvingScans(carvedWith),
                                 grids.window().reach(), initialBand(), slabOfTheData(data, team), ownSlabOf(data),
                                 mSettings.engine, interrupter);
}


void Reconstructor::requireWholeData(const char* what) const {
  if (mFusion && mFusion->forATeam())
    throw std::invalid_argument(std::string("Reconstructor::") + what +
                                ": the fusion holds one slab of the data or defers a grid (Fusion::restrictToSlab, "
                                "deferLevel): only the team's run() reconstructs from it");
}

openvdb::FloatGrid::Ptr Reconstructor::linearSolution(const Interrupter& interrupter) const {
  if (mSettings.levels > 1) requireFinestGridMemory(mSettings, initialModel(interrupter, mFusion).stats().activeSetVoxels);
  else requireCoarsestGridMemory(mSettings, bounds());
  if (mFusion)
    return mFusion->linearSolutionField(mSettings.levels - 1, LinearBand::kZeroCrossings, mSettings.engine, interrupter)
        .toLevelSet(3.0, mSettings.name);
  requireMapsAccumulationMemory(mSettings.levels - 1);
  const ForceField force(mMaps, forceOptions(mSettings.levels - 1));
  return force.linearSolution(mSettings.voxelSize, 3.0, mSettings.name, interrupter);
}

openvdb::FloatGrid::Ptr Reconstructor::surfaceWeight(const openvdb::FloatGrid& levelSet,
                                                     const Interrupter& interrupter) const {
  requireWholeData("surfaceWeight");
  const int finest = mSettings.levels - 1;
  if (mFusion) return levelfuse::surfaceWeight(levelSet, mFusion->dataTerm(finest), interrupter);
  if (mSettings.dataTerm == DataTermSource::kGrids)
    return levelfuse::surfaceWeight(levelSet, dataTermGrids(finest, interrupter), interrupter);
  return levelfuse::surfaceWeight(levelSet, ForceField(mMaps, forceOptions(finest)), interrupter);
}

openvdb::Vec3fGrid::Ptr Reconstructor::surfaceColour(const openvdb::FloatGrid& levelSet,
                                                     const Interrupter& interrupter) const {
  if (mSummary.colouredScans() == 0) return nullptr;
  const ForceFieldOptions f = forceOptions(mSettings.levels - 1);
  const RangeMapSequence maps = mFusion ? mFusion->scans() : rangeMapsOf(*mMaps);
  openvdb::Vec3fGrid::Ptr colour =
      levelfuse::surfaceColour(levelSet, maps, f.dataWindow(), f.positionVariance, interrupter);
  return colour->activeVoxelCount() > 0 ? colour : nullptr;
}


double Reconstructor::voxelSize(int level) const { return fusionSettingsOf(mSettings).levelVoxelSize(level); }

ForceFieldOptions Reconstructor::forceOptions(int level) const {
  return fusionSettingsOf(mSettings).levelForceOptions(level);
}

DataTermGrids Reconstructor::dataTermGrids(int level, const Interrupter& interrupter,
                                           const std::function<void(std::size_t)>& integrated) const {
  if (mFusion)
    throw std::invalid_argument("Reconstructor::dataTermGrids: the scans were integrated into a fusion: ask it "
                                "(Fusion::dataTerm)");
  requireMapsAccumulationMemory(level);
  const ForceFieldOptions f = forceOptions(level);
  DataTermGrids data(voxelSize(level), f.dataWindow(), f.positionVariance, f.grainSize);
  for (const RangeMap& map : *mMaps) {
    checkInterrupter(interrupter);
    data.integrate(map);
    if (integrated) integrated(data.mapCount());
  }
  return data;
}

template <typename Field>
LevelReport Reconstructor::evolveLevel(detail::EvolvingField& field, const Field& data, double h, ReconstructionProgress& state,
                                       const std::function<void()>& report) const {
  DataSpeed<Field> speed;
  speed.force = DataForce<Field>{&data};
  const double finest = mSettings.voxelSize;
  speed.beta = mSettings.beta * finest * finest;  // beta in voxels of the finest grid
  speed.sampling = ForceSampling::kSubcell;      // Eqs. 34-36
  if (speed.beta == 0.0) speed.force.limit = forceLimitWithoutPrior(h, mSettings.epsilon);
  LevelReport done;
  double slowest = std::numeric_limits<double>::infinity();
  int lastProgress = 0, snapshotIteration = 0;
  openvdb::FloatTree::Ptr snapshot = driftSnapshot(field, data);
  for (int iteration = 1; iteration <= mSettings.maxIterations; ++iteration) {
    const StepResult step = field.step(speed);
    done.simulatedTime += step.dt;
    state.iteration = iteration;
    state.activeSetVoxels = step.activeSetVoxels;
    // The surface the speed leaves at rest (no reading reaches it, no prior)
    // is not waited for.
    state.speed = step.dt > 0.0 ? step.rmsChangeNotAtRest / step.dt / h : 0.0;
    done.iterations = iteration;
    report();
    if (iteration < mSettings.minIterations) continue;
    if (state.speed < mSettings.tolerance || step.dt <= 0.0) {
      done.converged = true;
      break;
    }
    // Settled: the speed has stopped falling, and no region drifts. Points
    // whose zero crossing lies near the edge of their voxel keep trading
    // places with their neighbours, and noisy data keep the surface
    // trembling, so the speed of a settled surface does not reach zero; a
    // region still on its way (a lump of the initial model dissolving)
    // moves steadily one way, which the mean change over a leaf node shows.
    if (state.speed < 0.95 * slowest) {
      slowest = state.speed;
      lastProgress = iteration;
    }
    if (iteration - snapshotIteration >= mSettings.patience) {
      state.drift = field.largest(largestLocalDrift(field, *snapshot, data)) / h /
                    static_cast<double>(iteration - snapshotIteration);
      snapshot.reset();  // one copy at a time
      snapshot = driftSnapshot(field, data);
      snapshotIteration = iteration;
      if (iteration - lastProgress >= mSettings.patience && state.drift < mSettings.drift) {
        done.settled = true;
        break;
      }
    }
  }
  return done;
}

ReconstructionResult Reconstructor::run(const ProgressCallback& progress, const Interrupter& interrupter,
                                        const SlabTeam* team) const {
  const auto start = Clock::now();
  ReconstructionProgress state;
  state.levels = mSettings.levels;
  state.maxIterations = mSettings.maxIterations;
  const std::function<void()> report = [&] {
    state.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (progress && !progress(state)) throw ReconstructionCancelled();
  };

  ReconstructionResult result;
  state.voxelSize = voxelSize(0);
  report();
  // 1. The initial model: the linear solution on the coarsest grid, from the
  //    fusion's coarsest grid when the evolution takes the data term from
  //    grids: the scans are integrated into every grid at once, for both.
  PhaseClock clock;
  std::unique_ptr<Fusion> fused;
  const Fusion* fusion = mFusion;
  if (!fusion && mSettings.dataTerm == DataTermSource::kGrids) {
    clock.enter("integrating");
    fused = fuseScans(state, report, interrupter, team);
    fusion = fused.get();
  }
  if (fusion && fusion->forATeam() && !(team && team->size() > 1))
    throw std::invalid_argument("reconstruction: the fusion holds one slab of the data or defers a grid "
                                "(Fusion::restrictToSlab, deferLevel): run it with the team that shares the data");
  clock.enter("linear solution");
  state.stage = ReconstructionProgress::Stage::kInitialModel;
  state.scan = 0;
  state.scans = mSummary.scans();
  report();
  const auto carvedWith = [&](std::size_t scans) {
    state.scan = scans;
    report();
  };
  // A team's processes each keep their slab of the initial model, not the whole.
  detail::EvolvingField field = [&] {
    if (fusion && fusion->dataSlab()) {
      // Made of this process's slab of the data alone: the team counts the whole.
      detail::EvolvingField slab(initialSlab(interrupter, *fusion, carvedWith, *team), *team);
      requireFinestGridMemory(mSettings, slab.stats().activeSetVoxels, team);
      return slab;
    }
    SparseField initial = initialModel(interrupter, fusion, carvedWith);
    requireFinestGridMemory(mSettings, initial.stats().activeSetVoxels, team);
    if (team && team->size() > 1) return detail::EvolvingField(initial, *team);
    return detail::EvolvingField(std::move(initial));
  }();
  // 2-3. Each grid evolved, then refined for the next.
  int iterations = 0;
  for (int level = 0; level < mSettings.levels; ++level) {
    result.levels.push_back(reconstructLevel(level, field, fusion, state, report, interrupter, result, clock));
    iterations += result.levels.back().iterations;
    result.peakEngineBytes = std::max(result.peakEngineBytes, result.levels.back().engineBytes);
  }
  if (result.levelSet) {
    describeRun(*result.levelSet, iterations);
    clock.enter("colour");
    result.colour = surfaceColour(*result.levelSet, interrupter);
    if (mSettings.keepPieces) field.keepOwnPiece(result.levelSet, result.weight, result.colour);
  }
  clock.stop();
  result.phases = clock.phases();
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  state.stage = ReconstructionProgress::Stage::kDone;
  report();
  return result;
}

std::unique_ptr<Fusion> Reconstructor::fuseScans(ReconstructionProgress& state, const std::function<void()>& report,
                                                 const Interrupter& interrupter, const SlabTeam* team) const {
  std::unique_ptr<Fusion> fusion = fusionOnTeam(accumulationCostWithin(rangeMapsOf(*mMaps)), rangeMapsOf(*mMaps), mSettings,
                                               Fusion::Keep::kNothing, team, interrupter);
  state.stage = ReconstructionProgress::Stage::kIntegrating;
  state.scan = 0;
  state.scans = mMaps->size();
  for (const RangeMap& map : *mMaps) {
    checkInterrupter(interrupter);
    fusion->integrate(map);
    state.scan = fusion->scanCount();
    report();
  }
  return fusion;
}

LevelReport Reconstructor::reconstructLevel(int level, detail::EvolvingField& field, const Fusion* fusion,
                                            ReconstructionProgress& state,
                                            const std::function<void()>& report, const Interrupter& interrupter,
                                            ReconstructionResult& result, PhaseClock& clock) const {
  const auto levelStart = Clock::now();
  const double h = voxelSize(level);
  state.level = level;
  state.voxelSize = h;
  state.iteration = 0;
  state.drift = 0.0;
  if (level > 0) {
    // 3. Resample to half the voxel size.
    clock.enter("resampling");
    state.stage = ReconstructionProgress::Stage::kResampling;
    report();
    field.refine(mSettings.engine);
  }
  // 2. Evolve under the data term and the prior until the surface settles.
  // On the finest grid, the surface's weight is taken while its data term is at hand.
  const bool finestGrid = level + 1 == mSettings.levels;
  const auto evolveAndWeigh = [&](const auto& data) {
    clock.enter("evolution");
    state.stage = ReconstructionProgress::Stage::kEvolving;
    const LevelReport evolved = evolveLevel(field, data, h, state, report);
    if (finestGrid) {
      clock.enter("surface weight");
      // Pieces stay their slab's level set, ghosts and all, until the colour is made (run).
      detail::EvolvingField::Surface surface = field.release(
          mSettings.name,
          [&](const openvdb::FloatGrid& levelSet) { return levelfuse::surfaceWeight(levelSet, data, interrupter); },
          mSettings.keepPieces);
      result.levelSet = std::move(surface.levelSet);
      result.weight = std::move(surface.weight);
    }
    return evolved;
  };
  LevelReport done;
  if (fusion && fusion->deferred(level)) {
    clock.enter("integrating");
    const std::unique_ptr<DataTermGrids> slabData = dataTermOfSlab(level, field, *fusion, state, report, interrupter);
    done = evolveAndWeigh(*slabData);
    done.slabDataTermBytes = slabData->memoryBytes();
  } else if (fusion) {
    done = evolveAndWeigh(fusion->dataTerm(level));
  } else {
    done = evolveAndWeigh(ForceField(mMaps, forceOptions(level)));
  }
  const SparseFieldStats stats = field.stats();
  done.activeSetVoxels = stats.activeSetVoxels;
  done.bandVoxels = stats.bandVoxels;
  done.engineBytes = stats.memoryBytes;
  done.ownLeafNodes = field.ownLeafNodes();
  done.voxelSize = h;
  done.seconds = std::chrono::duration<double>(Clock::now() - levelStart).count();
  return done;
}

std::unique_ptr<DataTermGrids> Reconstructor::dataTermOfSlab(int level, const detail::EvolvingField& field,
                                                             const Fusion& fusion, ReconstructionProgress& state,
                                                             const std::function<void()>& report,
                                                             const Interrupter& interrupter) const {
  const std::optional<SlabBounds> own = field.slabBounds();
  if (!own) throw std::invalid_argument("reconstruction: a deferred grid's data term is integrated by a team");
  const SlabBounds data = dataSlabOf(*own);
  // This reconstructor's maps for a fusion made by run(), which keeps none; else the fusion's own.
  const RangeMapSequence scans = mFusion ? RangeMapSequence{} : rangeMapsOf(*mMaps);
  const auto [xMin, xMax] = worldRangeOf(data, voxelSize(level));
  const AccumulationCostWithin costWithin = accumulationCostWithin(scans ? scans : fusion.scans());
  requireAccumulationMemory(
      [&, xMin = xMin, xMax = xMax](double h, double reach) { return costWithin(h, reach, xMin, xMax); }, mSettings,
      level);
  state.stage = ReconstructionProgress::Stage::kIntegrating;
  report();
  std::unique_ptr<DataTermGrids> grids = fusion.dataTermWithin(level, data, interrupter, scans);
  returnFreedMemory();  // the terms of each batch of leaves, made on the worker threads' heaps
  return grids;
}

void Reconstructor::describeRun(openvdb::FloatGrid& out, int iterations) const {
  out.insertMeta("levelfuse_version", openvdb::StringMetadata(version()));
  out.insertMeta("levelfuse_voxel_size", openvdb::DoubleMetadata(mSettings.voxelSize));
  out.insertMeta("levelfuse_levels", openvdb::Int32Metadata(mSettings.levels));
  out.insertMeta("levelfuse_beta", openvdb::DoubleMetadata(mSettings.beta));
  out.insertMeta("levelfuse_epsilon", openvdb::DoubleMetadata(mSettings.epsilon));
  out.insertMeta("levelfuse_window", openvdb::StringMetadata(windowKindName(mSettings.window)));
  out.insertMeta("levelfuse_data_term",
                 openvdb::StringMetadata(mSettings.dataTerm == DataTermSource::kGrids ? "grids" : "maps"));
  out.insertMeta("levelfuse_tolerance", openvdb::DoubleMetadata(mSettings.tolerance));
  out.insertMeta("levelfuse_iterations", openvdb::Int32Metadata(iterations));
  out.insertMeta("levelfuse_scans", openvdb::Int32Metadata(static_cast<int>(mSummary.scans())));
}

ReconstructionResult reconstruct(const Fusion& fusion, const ReconstructionOptions& options,
                                 const ProgressCallback& progress, const Interrupter& interrupter) {
  return Reconstructor(fusion, options).run(progress, interrupter);
}

}  // namespace levelfuse
