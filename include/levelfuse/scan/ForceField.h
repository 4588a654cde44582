// levelfuse: the MAP data term of a set of range maps (paper section 3, Eq. 17).
//
//   g(x) = sum_j c_j(x) D_j(x) w(D_j(x)) gamma_j(x)
//
// with the window w limiting each reading's reach along its line of sight
// (Eqs. 8-9), the confidence c_j = 1 / (sigma_r^2 + |grad D_j|^2 sigma_x^2)
// (Eq. 38) and the ray density gamma_j. g > 0 where x lies behind the data: the
// surface moves outward there. Without a prior the MAP surface is the zero
// set of g, the linear solution; it is the initial model of the evolution.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/scan/CarvingMemo.h>
#include <levelfuse/scan/DataTermGrids.h>
#include <levelfuse/scan/DataWindow.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace levelfuse {

struct ForceFieldOptions {
  WindowKind window = WindowKind::kGaussian;
  double epsilon = 0.0;   ///< window width (world units); must be set
  double reach = 3.0;     ///< the Gaussian window is cut at reach * epsilon
  /// sigma_x^2 of Eq. 38 (world units squared): the model's positional
  /// uncertainty, voxelSize^2 / 12 without and about voxelSize^2 / 120 with
  /// subcell positioning (section 6).
  double positionVariance = 0.0;
  std::size_t grainSize = 1;  ///< leaf nodes per parallel task; 0 runs serially

  /// The window these options describe; throws std::invalid_argument for an
  /// epsilon or reach that is not positive and finite.
  DataWindow dataWindow() const { return DataWindow(window, epsilon, reach); }
};

/// The data term's settings on a grid of `voxelSize` for a window of width
/// `epsilon`: the window never narrows below a voxel of the grid (eps =
/// max(epsilon, voxelSize)), so that a reading reaches at least a voxel either
/// side of the surface, and the positional variance is that of subcell
/// positioning, voxelSize^2 / 120 (Eq. 38, section 6). The one rule the
/// Reconstructor's grids follow.
ForceFieldOptions forceFieldOptions(double epsilon, double voxelSize, WindowKind window = WindowKind::kGaussian);

/// forceFieldOptions for a Gaussian window as wide as the range maps' median
/// noise sigma: a reading reaches as far as its own uncertainty. The
/// Reconstructor's defaults.
ForceFieldOptions defaultForceFieldOptions(const std::vector<RangeMap>& maps, double voxelSize);

/// Where the data term reaches, accumulated on a grid: the terms of Eq. 17
/// summed per voxel, and their weights.
struct AccumulatedField {
  openvdb::FloatGrid::Ptr g;       ///< sum_j c_j D_j w_j gamma_j, active where some window reaches
  openvdb::FloatGrid::Ptr weight;  ///< sum_j c_j w_j gamma_j, same topology
  std::size_t evaluations = 0;     ///< (voxel, range map) pairs evaluated
};

/// How the linear solution's narrow band is made from its field: the
/// distances to the data where a window reaches, and carving's steps.
enum class LinearBand {
  /// The sparse field's active set at the field's zero crossings, each value
  /// the distance to the plane through the points where the zero set crosses
  /// the voxel's edges; specks of one sign under 2 x 2 x 2 voxels are left
  /// out, everything else the grid resolves is kept, structures a voxel thin
  /// included. The finest grid's linear solution.
  kZeroCrossings,
  /// Rebuilt through a mesh of the zero set into Euclidean distances
  /// (tools::levelSetRebuild), which leaves out structures thinner than a
  /// voxel: the initial model on the coarsest grid of a coarse-to-fine run,
  /// where they are noise against the grid, and the finer grids bring back
  /// what the data support.
  kRebuilt,
};

/// One slab of the data, as a process of a team holds it when the team
/// shares the data slab by slab (recon/SharedData.h): the data term
/// accumulated within `data` alone (DataTermGrids::restrictToSlab), and what
/// the processes agree on, the box of every process's data.
struct SlabOfTheData {
  SlabBounds data;
  /// The box of the blocks (leaf-node-sized cells, index space divided by 8)
  /// that every process's data reach, from this process's: a reduction over
  /// the team (an empty box where a process has no data).
  std::function<openvdb::CoordBBox(const openvdb::CoordBBox&)> wholeDataBlocks;
};

/// How far into a slab of the data (SlabOfTheData) its linear solution may
/// differ from the whole data's, in voxels from each face the data end at:
/// the blocks beside a face take the data beyond it for carved space, and
/// whether they carve depends on it (one block, 8 voxels); a speck reaching
/// them spans at most 7 voxels more, and its neighbours one more
/// (kSpeckVoxels); a distance at a zero crossing reads a voxel beyond. Beyond
/// it every value and active voxel is the whole data's, bit for bit (tested).
inline constexpr int kLinearSolutionSlabMargin = 8 + 8 + 1;

/// The linear solution of an accumulated data term (ForceField::accumulate,
/// or DataTermGrids' gGrid and weightGrid) as a sparse field with the
/// engine's settings `engine`, ready to evolve, its narrow band made as `band`
/// says: where the data reach, the sign of -g; elsewhere space carving
/// against `maps` with readings `margin` thick (the window's reach) decides
/// (ForceField::linearSolution). Carving visits the maps twice, one at a
/// time, so that they need not be held at once. Throws std::invalid_argument
/// if no reading reaches any voxel, Interrupted if `interrupter` asks to stop.
/// `data`'s grids are let go as soon as the data's leaves are made (when no
/// copy of them is held elsewhere, e.g. moved in): carving's second round and
/// the narrow band do not hold them.
SparseField linearSolutionField(AccumulatedField data, const RangeMapSequence& maps, double margin,
                                LinearBand band, const SparseFieldOptions& engine = {},
                                const Interrupter& interrupter = {});
/// The same for the first `mapCount` maps of a sequence that grows between
/// calls (a fusion's maps while frames keep coming), `maps` visiting them
/// from any on: carving starts from the votes `memo` kept from the last call
/// and keeps its votes there, so that it asks only the new maps of what it
/// asked before; the same field as carving from scratch, bit for bit.
SparseField linearSolutionField(AccumulatedField data, const RangeMapsFrom& maps, std::size_t mapCount,
                                CarvingMemo& memo, double margin, LinearBand band, const SparseFieldOptions& engine = {},
                                const Interrupter& interrupter = {});
/// The same of one slab of the data (`slab`), as the slab `own` of the whole
/// data's sparse field (SlabField::fromLevelSet): exact where `own` lies
/// kLinearSolutionSlabMargin voxels and the layers' reach within the data.
/// The blocks carving decides are the whole data's box cut to the slab's data
/// and one block beyond; a slab with no data, or no surface, is empty. Every
/// process of the team calls it: the box is agreed on before anything else.
SlabField linearSolutionSlabField(AccumulatedField data, const RangeMapSequence& maps, double margin, LinearBand band,
                                  const SlabOfTheData& slab, const SlabBounds& own,
                                  const SparseFieldOptions& engine = {}, const Interrupter& interrupter = {});
/// The same, of a vector of range maps.
SparseField linearSolutionField(AccumulatedField data, const std::vector<RangeMap>& maps, double margin,
                                LinearBand band, const SparseFieldOptions& engine = {},
                                const Interrupter& interrupter = {});

class ForceField {
 public:
  ForceField(std::vector<RangeMap> maps, const ForceFieldOptions& options);
  /// Shares the range maps, e.g. between the force fields of several grids.
  ForceField(std::shared_ptr<const std::vector<RangeMap>> maps, const ForceFieldOptions& options);

  /// g(x), Eq. 17.
  double g(const openvdb::Vec3d& x) const;
  /// g~(x, N), Eq. 37: only the range maps whose scanner the surface at x, with
  /// outward normal N, faces (n_j . N < 0) contribute.
  double facing(const openvdb::Vec3d& x, const openvdb::Vec3d& normal) const;
  /// Sum of the weights c_j w_j gamma_j at x.
  double weight(const openvdb::Vec3d& x) const;
  /// Sum of the windows w_j at x: how many readings reach x, a reading whose
  /// window is 1 there counting one.
  double readings(const openvdb::Vec3d& x) const;

  /// The facing-checked data term at x (Eq. 37), its weight and its readings:
  /// the sums of c_j D_j w_j gamma_j, c_j w_j gamma_j and w_j over the range maps whose
  /// scanner a surface through x with outward normal N faces. The hot path of
  /// the evolution: maps whose windows cannot reach x are skipped at once.
  using Terms = DataTerms;
  Terms facingTerms(const openvdb::Vec3d& x, const openvdb::Vec3d& normal) const;

  /// Accumulates g over the voxels (of size `voxelSize`, centred on multiples
  /// of it) within the window of some reading. Parallel over leaf nodes and
  /// deterministic; memory grows with the scanned surface.
  /// `interrupter` is asked once per range map and leaf node (Interrupted).
  AccumulatedField accumulate(double voxelSize, const Interrupter& interrupter = {}) const;

  /// The linear solution: the zero set of g as an OpenVDB level set (negative
  /// inside, half-width `halfWidth` voxels, GRID_LEVEL_SET), the VRIP-style
  /// fusion of the scans. Where the data reaches, the sign is that of -g (the
  /// weighted mean signed distance -sum(c D w gamma) / sum(c w gamma) along the
  /// lines of sight); elsewhere space carving decides: a point some line of
  /// sight saw as empty is outside, else a point behind some reading is inside,
  /// else outside. Surfaces no scan saw thus close along the boundary of the
  /// observed empty space. The narrow band is the sparse field's, built at the
  /// zero crossings (LinearBand::kZeroCrossings).
  openvdb::FloatGrid::Ptr linearSolution(double voxelSize, double halfWidth = 3.0,
                                         const std::string& name = "surface",
                                         const Interrupter& interrupter = {}) const;
  /// The linear solution as a sparse field with the engine's settings
  /// `engine`, ready to evolve, its narrow band made as `band` says.
  SparseField linearSolutionField(double voxelSize, LinearBand band, const SparseFieldOptions& engine = {},
                                  const Interrupter& interrupter = {}) const;

  const std::vector<RangeMap>& maps() const { return *mMaps; }
  const ForceFieldOptions& options() const { return mOptions; }

 private:
  /// Range map j's term at x; false if it has none.
  bool term(std::size_t j, const openvdb::Vec3d& x, DataTerms& t, openvdb::Vec3d* lineOfSight) const;
  /// The terms of all range maps at x, without the facing check.
  DataTerms allTerms(const openvdb::Vec3d& x) const;

  std::shared_ptr<const std::vector<RangeMap>> mMaps;
  /// Per map: the world box its windows reach, and its line of sight where it
  /// is one direction for all pixels (parallel rays), else zero.
  std::vector<openvdb::BBoxd> mReach;
  std::vector<openvdb::Vec3d> mParallelSight;
  ForceFieldOptions mOptions;
  DataWindow mWindow;
};

}  // namespace levelfuse
