// levelfuse: range maps fused one at a time, as depth video arrives: each
// map's data term goes into the grids of every level of the coarse-to-fine
// run at once (DataTermGrids), and the map is kept packed (PackedRangeMap)
// for space carving, so the caller releases it at once. The linear solution
// and the MAP reconstruction can be asked for at any time, as often as
// wanted, while more maps keep coming: the grids are reused, never
// integrated again.
//
//   Fusion fusion(FusionSettings{0.01, 1, 0.006});
//   for (each frame) fusion.integrate(io::depthFrame(image, intrinsics, pose, io::DepthNoise{}, name));
//   openvdb::FloatGrid::Ptr linear = fusion.linearSolution();
//   ReconstructionResult result = reconstruct(fusion);  // recon/Reconstructor.h
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/recon/FusionSettings.h>
#include <levelfuse/recon/MemoryPlan.h>
#include <levelfuse/recon/ReconstructionOptions.h>
#include <levelfuse/scan/DataTermGrids.h>
#include <levelfuse/scan/ForceField.h>
#include <levelfuse/scan/PackedRangeMap.h>
#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/scan/ScanSummary.h>

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace levelfuse {

class SlabTeam;
struct SharedDataSlab;

class Fusion {
 public:
  /// What the fusion keeps of each map for space carving.
  enum class Keep {
    kPacked,  ///< a packed copy (PackedRangeMap): the maps may be released
    kNothing  ///< nothing: whoever asks for a linear solution hands the maps in again
  };
  /// Throws std::invalid_argument for settings that cannot be used, with a hint.
  explicit Fusion(const FusionSettings& settings, Keep keep = Keep::kPacked);

  /// Adds `map`'s data term to the grids of every level; the map may be
  /// released afterwards. Deterministic for a given order of maps, whatever
  /// the number of threads.
  void integrate(const RangeMap& map);
  /// The same for a map already packed (read ahead and held packed, e.g. while
  /// the settings were derived from every map's summary): unpacked for the
  /// integration, then kept as it is (or dropped, Keep::kNothing).
  void integrate(PackedRangeMap packed);
  /// The same for many maps, in order, unpacked a few at a time in parallel
  /// (visitUnpacked); `integrated`, if set, is told after each map how many
  /// of how many are in. Interrupted if `interrupter` asks to stop between
  /// maps: those integrated so far are kept.
  void integrate(std::vector<PackedRangeMap> maps,
                 const std::function<void(std::size_t, std::size_t)>& integrated = {},
                 const Interrupter& interrupter = {});

  /// From now on the fusion's grid takes terms within `data` alone
  /// (DataTermGrids::restrictToSlab): the part of the data term one process
  /// of a team reads (recon/SharedData.h). A fusion of one grid, before its
  /// first map; throws std::invalid_argument otherwise.
  void restrictToSlab(const SlabBounds& data);
  /// The x range of the data the grid holds (restrictToSlab), or none: all.
  const std::optional<SlabBounds>& dataSlab() const { return mDataSlab; }
  /// From now on grid `level` takes no terms: the processes of a team that
  /// share a coarse-to-fine reconstruction each integrate it within their
  /// slab of it once it is cut (dataTermWithin). Before the first map;
  /// throws std::invalid_argument otherwise, or for the coarsest grid, whose
  /// data make the initial model.
  void deferLevel(int level);
  /// Whether grid `level` was deferred (deferLevel).
  bool deferred(int level) const { return mDeferred.at(static_cast<std::size_t>(level)); }
  /// Whether only a team's reconstruction can use the fusion: it holds one
  /// slab of the data (restrictToSlab) or defers a grid (deferLevel).
  bool forATeam() const {
    return mDataSlab.has_value() || std::find(mDeferred.begin(), mDeferred.end(), true) != mDeferred.end();
  }
  /// The data term of grid `level` within the slab `data` alone
  /// (DataTermGrids::restrictToSlab), of `scans` (by default, the maps
  /// kept), unpacked a few at a time: the whole grid's terms there, bit for
  /// bit. Throws std::invalid_argument without maps; Interrupted if
  /// `interrupter` asks to stop between maps.
  std::unique_ptr<DataTermGrids> dataTermWithin(int level, const SlabBounds& data, const Interrupter& interrupter = {},
                                                const RangeMapSequence& scans = {}) const;

  /// From now on the fusion's summary is `whole`'s, the summary of every scan
  /// of a reconstruction of which it integrated a part: a process of a team
  /// that read the scans its slab needs (recon/TeamScans.h) derives the
  /// team's settings, and counts the team's scans.
  void adoptSummary(ScanSummary whole) { mSummary = std::move(whole); }
  std::size_t scanCount() const { return mSummary.scans(); }
  const ScanSummary& summary() const { return mSummary; }
  const FusionSettings& settings() const { return mSettings; }
  int levels() const { return mSettings.levels; }
  /// Voxel size of grid `level` (0 is the coarsest).
  double voxelSize(int level) const { return mSettings.levelVoxelSize(level); }
  /// The data term accumulated on grid `level`.
  const DataTermGrids& dataTerm(int level) const { return *mGrids.at(static_cast<std::size_t>(level)); }
  /// The maps kept (Keep::kPacked), unpacked one at a time.
  RangeMapSequence scans() const;
  /// The maps kept and their summary, moved out (the fusion keeps its grids
  /// and no maps): for a caller that needs the maps after the reconstruction
  /// and can let the grids go.
  PackedScans takeScans();

  /// The linear solution on grid `level` as a sparse field (linearSolutionField),
  /// space carving asking `scans` (by default, the maps kept: then, with
  /// FusionSettings::keepCarvingVotes, from the votes kept from the last
  /// answer on the grid, whose new maps alone are asked of what it asked). Throws
  /// std::invalid_argument before any reading, or without maps to carve with;
  /// Interrupted if `interrupter` asks to stop.
  SparseField linearSolutionField(int level, LinearBand band, const SparseFieldOptions& engine = {},
                                  const Interrupter& interrupter = {}, const RangeMapSequence& scans = {}) const;
  /// The linear solution on the finest grid as an OpenVDB level set
  /// (half-width 3, GRID_LEVEL_SET): VRIP-style fusion of the maps so far.
  openvdb::FloatGrid::Ptr linearSolution(const std::string& name = "surface", const Interrupter& interrupter = {}) const;

  /// Memory held (bytes): the grids, the packed maps and carving's votes kept.
  std::size_t memoryBytes() const;
  /// Memory held by the grids of the data term alone (bytes).
  std::size_t dataTermBytes() const;

 private:
  /// Adds the map's data term to every grid and its facts to the summary.
  void addToGrids(const RangeMap& map);

  FusionSettings mSettings;
  Keep mKeep;
  std::vector<std::unique_ptr<DataTermGrids>> mGrids;  ///< per level, coarsest first
  std::vector<PackedRangeMap> mPacked;
  /// Per level: carving's votes kept between linear solutions (FusionSettings::keepCarvingVotes).
  mutable std::vector<CarvingMemo> mCarvingMemos;
  ScanSummary mSummary;
  std::optional<SlabBounds> mDataSlab;
  std::vector<bool> mDeferred;  ///< per level: integrated later, within a slab (deferLevel)
};

/// An empty fusion of the settings' grids (fusionSettingsOf), once
/// requireAccumulationMemory has found that the data term of the scans whose
/// cost `costOf` finds fits on every grid (InsufficientMemory if not); with
/// `deferFinerGrids`, every grid but the coarsest deferred (Fusion::deferLevel)
/// and not checked.
std::unique_ptr<Fusion> fusionFor(const AccumulationCostOf& costOf, const ReconstructionSettings& settings,
                                  Fusion::Keep keep, bool deferFinerGrids = false);


}  // namespace levelfuse
