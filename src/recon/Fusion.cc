// levelfuse: range maps fused one at a time.

#include <levelfuse/recon/Fusion.h>

#include <tbb/task_group.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace levelfuse {

namespace {

/// The empty grids of the data term of `level` of `settings`.
std::unique_ptr<DataTermGrids> emptyDataTerm(const FusionSettings& settings, int level) {
  const ForceFieldOptions f = settings.levelForceOptions(level);
  return std::make_unique<DataTermGrids>(settings.levelVoxelSize(level), f.dataWindow(), f.positionVariance,
                                         f.grainSize);
}

}  // namespace

Fusion::Fusion(const FusionSettings& settings, Keep keep) : mSettings(settings), mKeep(keep) {
  if (!(settings.voxelSize >= kSmallestVoxelSize) || !std::isfinite(settings.voxelSize))
    throw std::invalid_argument("Fusion: the voxel size must be finite and at least " +
                                std::to_string(kSmallestVoxelSize) + " (give the maps in metres)");
  if (settings.levels < 1 || settings.levels > 12)
    throw std::invalid_argument("Fusion: the number of grids (levels) must be 1 to 12");
  if (!(settings.epsilon > 0.0) || !std::isfinite(settings.epsilon))
    throw std::invalid_argument("Fusion: the window width epsilon must be positive: about the maps' noise sigma");
  for (int level = 0; level < settings.levels; ++level) mGrids.push_back(emptyDataTerm(settings, level));
  mCarvingMemos.resize(static_cast<std::size_t>(settings.levels));
  mDeferred.assign(static_cast<std::size_t>(settings.levels), false);
}

double FusionSettings::levelVoxelSize(int level) const { return std::ldexp(voxelSize, levels - 1 - level); }

ForceFieldOptions FusionSettings::levelForceOptions(int level) const {
  ForceFieldOptions f = forceFieldOptions(epsilon, levelVoxelSize(level), window);
  f.grainSize = grainSize == 0 ? 0 : 1;
  return f;
}

void Fusion::restrictToSlab(const SlabBounds& data) {
  if (levels() != 1)
    throw std::invalid_argument("Fusion::restrictToSlab: only a fusion of one grid holds a slab of the data (it has " +
                                std::to_string(levels()) + ")");
  if (scanCount() > 0)
    throw std::invalid_argument("Fusion::restrictToSlab: the fusion holds maps already: restrict it before the first");
  mGrids.front()->restrictToSlab(data.begin, data.end);
  mDataSlab = data;
}

void Fusion::deferLevel(int level) {
  if (level < 1 || level >= levels())
    throw std::invalid_argument("Fusion::deferLevel: grid " + std::to_string(level) + " of " +
                                std::to_string(levels()) + " (the coarsest makes the initial model)");
  if (scanCount() > 0)
    throw std::invalid_argument("Fusion::deferLevel: the fusion holds maps already: defer a grid before the first");
  mDeferred[static_cast<std::size_t>(level)] = true;
}

std::unique_ptr<DataTermGrids> Fusion::dataTermWithin(int level, const SlabBounds& data, const Interrupter& interrupter,
                                                      const RangeMapSequence& scans) const {
  if (!scans && mKeep != Keep::kPacked)
    throw std::invalid_argument("Fusion: it keeps no maps (Keep::kNothing): hand in the maps to integrate");
  std::unique_ptr<DataTermGrids> grids = emptyDataTerm(mSettings, level);
  grids->restrictToSlab(data.begin, data.end);
  (scans ? scans : this->scans())([&](const RangeMap& map) {
    checkInterrupter(interrupter);
    grids->integrate(map);
  });
  return grids;
}

void Fusion::addToGrids(const RangeMap& map) {
  for (std::size_t level = 0; level < mGrids.size(); ++level)
    if (!mDeferred[level]) mGrids[level]->integrate(map);
  mSummary.add(map);
}

void Fusion::integrate(const RangeMap& map) {
  if (mKeep != Keep::kPacked) {
    addToGrids(map);
    return;
  }
  // The packed copy is made on another thread while the grids take the map:
  // packing is serial, and so are the parts of an integration that change
  // the grids' trees.
  std::optional<PackedRangeMap> packed;
  tbb::task_group packing;
  packing.run([&] { packed.emplace(RangeMap(map)); });
  try {
    addToGrids(map);
  } catch (...) {
    packing.wait();
    throw;
  }
  packing.wait();
  mPacked.push_back(std::move(*packed));
}

void Fusion::integrate(PackedRangeMap packed) {
  addToGrids(packed.unpack());
  if (mKeep == Keep::kPacked) mPacked.push_back(std::move(packed));
}

void Fusion::integrate(std::vector<PackedRangeMap> maps, const std::function<void(std::size_t, std::size_t)>& integrated,
                       const Interrupter& interrupter) {
  std::size_t next = 0;
  visitUnpacked(maps, [&](const RangeMap& map) {
    checkInterrupter(interrupter);
    addToGrids(map);
    // Map `next` is the one visited: unpacked already, it may be moved from.
    if (mKeep == Keep::kPacked) mPacked.push_back(std::move(maps[next]));
    ++next;
    if (integrated) integrated(scanCount(), maps.size());
  });
}

RangeMapSequence Fusion::scans() const {
  return [this](const RangeMapVisitor& visit) { visitUnpacked(mPacked, visit); };
}

PackedScans Fusion::takeScans() {
  PackedScans taken;
  taken.maps = std::move(mPacked);
  taken.summary = std::move(mSummary);
  mPacked.clear();
  mSummary = ScanSummary();
  for (CarvingMemo& memo : mCarvingMemos) memo.clear();
  return taken;
}

SparseField Fusion::linearSolutionField(int level, LinearBand band, const SparseFieldOptions& engine,
                                        const Interrupter& interrupter, const RangeMapSequence& scans) const {
  if (mSummary.readings() == 0) throw std::invalid_argument("Fusion: no reading integrated yet");
  if (mDataSlab)
    throw std::invalid_argument("Fusion: it holds one slab of the data (restrictToSlab): only its team's "
                                "reconstruction makes a linear solution of it");
  if (deferred(level))
    throw std::invalid_argument("Fusion: grid " + std::to_string(level) +
                                " was deferred (deferLevel): only its team's reconstruction integrates it");
  if (!scans && mKeep != Keep::kPacked)
    throw std::invalid_argument("Fusion: it keeps no maps (Keep::kNothing): hand in the maps to carve with");
  const DataTermGrids& grids = dataTerm(level);
  // The summed grids are handed over, not copied: the linear solution lets
  // them go once carving no longer needs them.
  AccumulatedField data{grids.gGrid(), grids.weightGrid(), 0};
  if (scans || !mSettings.keepCarvingVotes)
    return levelfuse::linearSolutionField(std::move(data), scans ? scans : this->scans(), grids.window().reach(), band,
                                          engine, interrupter);
  const RangeMapsFrom keptFrom = [this](std::size_t first, const NumberedRangeMapVisitor& visit) {
    visitUnpacked(mPacked, first, visit);
  };
  return levelfuse::linearSolutionField(std::move(data), keptFrom, mPacked.size(),
                                        mCarvingMemos.at(static_cast<std::size_t>(level)), grids.window().reach(), band,
                                        engine, interrupter);
}

openvdb::FloatGrid::Ptr Fusion::linearSolution(const std::string& name, const Interrupter& interrupter) const {
  return linearSolutionField(levels() - 1, LinearBand::kZeroCrossings, SparseFieldOptions{}, interrupter)
      .toLevelSet(3.0, name);
}

std::size_t Fusion::memoryBytes() const {
  std::size_t bytes = sizeof(*this) + dataTermBytes();
  for (const PackedRangeMap& p : mPacked) bytes += p.memoryBytes();
  for (const CarvingMemo& memo : mCarvingMemos) bytes += memo.memoryBytes();
  return bytes;
}

std::size_t Fusion::dataTermBytes() const {
  std::size_t bytes = 0;
  for (const std::unique_ptr<DataTermGrids>& grids : mGrids) bytes += grids->memoryBytes();
  return bytes;
}

std::unique_ptr<Fusion> fusionFor(const AccumulationCostOf& costOf, const ReconstructionSettings& settings,
                                  Fusion::Keep keep, bool deferFinerGrids) {
  FusionSettings grids = fusionSettingsOf(settings);
  grids.keepCarvingVotes = false;  // one answer, after the last map
  const int checked = deferFinerGrids ? 1 : grids.levels;
  for (int level = 0; level < checked; ++level) requireAccumulationMemory(costOf, settings, level);
  std::unique_ptr<Fusion> fusion = std::make_unique<Fusion>(grids, keep);
  if (deferFinerGrids)
    for (int level = 1; level < grids.levels; ++level) fusion->deferLevel(level);
  return fusion;
}

}  // namespace levelfuse
