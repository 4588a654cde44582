// levelfuse: the MAP data term accumulated on sparse grids, one range map at
// a time, so that the evolution samples grids and never the scans.
//
// Per voxel p and per direction bin b of the lines of sight (SightBins.h), the
// grids hold the sums over the range maps j whose line of sight at p falls in b
//
//   G_b(p) = sum_j c_j D_j w_j gamma_j           (the terms of g, Eq. 17)
//   W_b(p) = sum_j c_j w_j gamma_j               (their weights)
//   V_b(p) = sum_j c_j w_j gamma_j grad D_j      (the weighted gradients of D)
//
// with the window w (Eqs. 8-9) and the confidence c (Eq. 38), and per leaf
// node and bin the weighted sum of the lines of sight n_j,
//
//   S_b(leaf) = sum over the leaf's voxels and the maps j of c_j w_j gamma_j n_j
//
// (lines of sight turn slowly in space: a leaf of a 1 cm grid 2 m from a camera
// spans 2.3 degrees of its rays), and the sums of the weights and of the
// windows, whose ratio is the weight R_b of one reading there:
//
//   R_b(leaf) = sum c_j w_j gamma_j / sum w_j     (over the leaf's voxels and the maps)
//
// (a reading's weight changes slowly too: with its depth, as 1 / (z^2 sigma(z)^2)
// for a depth camera). At a point x and an outward normal N the
// facing-checked term g~ (Eq. 37) is the sum over the bins whose mean line of
// sight faces the surface (S_b . N < 0), each bin's terms taken from the
// eight voxels around x, each voxel's term carried to x along its gradient:
//
//   G_b(x) = sum_k t_k (G_b(p_k) + V_b(p_k) . (x - p_k)),   W_b(x) = sum_k t_k W_b(p_k)
//
// with t_k the trilinear weights, and the number of readings that reach x,
// N_b(x) = W_b(x) / R_b. A single reading of a planar surface thus
// gives D(x) = G_b(x) / W_b(x) exactly at any x between voxels, as the
// per-map evaluation does. The approximation against Eq. 37 evaluated per map
// is the facing check made per bin and leaf on the mean line of sight (maps
// that share a bin are at most 71 degrees apart), the weights interpolated
// between voxels, and the readings' curvature between voxels:
// docs/RECONSTRUCTION.md measures what it costs.
#pragma once

#include <levelfuse/scan/DataWindow.h>
#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/scan/SightBins.h>

#include <openvdb/openvdb.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

namespace levelfuse {

namespace detail {
class CellSpans;
class UsableSpans;
struct BatchTerms;    // DataTermGrids.cc
struct BatchTargets;  // DataTermGrids.cc
}  // namespace detail

/// The sums of a data term at a point over the readings whose windows reach
/// it: sum c D w gamma (the terms of g), sum c w gamma (their weight) and
/// sum w (how many readings reach the point, one whose window is 1 there
/// counting one).
struct DataTerms {
  double g = 0.0;
  double weight = 0.0;
  double readings = 0.0;
  DataTerms& operator+=(const DataTerms& t) {
    g += t.g;
    weight += t.weight;
    readings += t.readings;
    return *this;
  }
};

class DataTermGrids {
 public:
  /// Grids of voxel size `voxelSize` (voxel centres at multiples of it) for a
  /// data term of the given window, and sigma_x^2 of Eq. 38 (world units
  /// squared). Throws std::invalid_argument for a voxel size that is not
  /// positive and finite or a negative variance.
  DataTermGrids(double voxelSize, const DataWindow& window, double positionVariance, std::size_t grainSize = 1);

  /// Leaf nodes whose terms integrate holds at once (a few megabytes: the
  /// terms, the target leaves and the sums of each), a batch after another.
  static constexpr std::size_t kLeavesPerBatch = 2048;

  /// Adds the terms of one range map to every voxel its windows reach; the
  /// map may be released afterwards. Parallel over leaf nodes; the sums are
  /// deterministic for a given order of maps, whatever the number of threads.
  void integrate(const RangeMap& map);

  /// From now on only the leaf nodes whose origin x (in voxels of these
  /// grids) lies in [begin, end) take terms: the part of the grids that one
  /// slab of a field shared by processes reads (levelset/SlabField.h). Their
  /// sums are those of unrestricted grids, bit for bit, when the same maps
  /// reaching them come in the same order. Throws std::invalid_argument
  /// unless begin < end.
  void restrictToSlab(openvdb::Int32 begin, openvdb::Int32 end);

  /// The queries below as one task asks them, point after point of a leaf
  /// node: the same answers, bit for bit, through tree accessors of its own
  /// that keep the nodes the points share.
  class Sampler;
  Sampler sampler() const;

  /// g~(x), its weight and its readings for a surface through x with outward normal N (Eq. 37).
  DataTerms facingTerms(const openvdb::Vec3d& x, const openvdb::Vec3d& normal) const;
  /// The total weight sum_j c_j w_j gamma_j at x, all directions (interpolated).
  double weight(const openvdb::Vec3d& x) const;
  /// The number of readings that reach x, all directions (sum_b N_b(x)).
  double readings(const openvdb::Vec3d& x) const;
  /// False only if no term reaches any point of the world box `world`: then
  /// facingTerms, weight and readings are zero everywhere in it.
  bool mayHaveTermsIn(const openvdb::BBoxd& world) const;

  /// g and its weight summed over all bins, per voxel (GRID_UNKNOWN, named "g"
  /// and "weight"): the field whose zero set is the linear solution.
  openvdb::FloatGrid::Ptr gGrid() const;
  openvdb::FloatGrid::Ptr weightGrid() const;

  std::size_t mapCount() const { return mMapCount; }
  double voxelSize() const { return mVoxelSize; }
  const DataWindow& window() const { return mWindow; }
  /// (voxel, range map) pairs evaluated so far.
  std::size_t evaluations() const { return mEvaluations; }
  /// Memory held by the grids (bytes).
  std::size_t memoryBytes() const;

 private:
  struct Bin {
    openvdb::FloatGrid::Ptr g, weight;
    openvdb::Vec3fGrid::Ptr gradient;
    openvdb::Vec3fGrid::Ptr sight;  ///< S_b, one voxel per leaf node (voxel size 8 h)
    /// Per leaf node (voxel size 8 h): sum c w gamma and sum w, whose ratio is R_b.
    openvdb::FloatGrid::Ptr leafWeight, leafWindows;
  };
  /// Adds the terms of `map` at the leaf nodes [leaves, leaves + count), in
  /// their order (`cells` and `spans`: the map's readings per cell and per block).
  void integrateLeaves(const RangeMap& map, const detail::CellSpans& cells, const detail::UsableSpans& spans,
                       const openvdb::Coord* leaves, std::size_t count);
  /// The leaves of the grids that the terms of `batch`, one map's at the leaf
  /// nodes [leaves, leaves + count), go into: made, each tree's serially
  /// (its topology), the trees in parallel.
  detail::BatchTargets touchTargetLeaves(const detail::BatchTerms& batch, const openvdb::Coord* leaves);
  /// The bin mask's leaves of touchTargetLeaves.
  void touchMaskLeaves(const detail::BatchTerms& batch, const openvdb::Coord* leaves, detail::BatchTargets& targets);
  /// Bin b's leaves of touchTargetLeaves, of each of its grids.
  void touchBinLeaves(std::size_t b, const detail::BatchTerms& batch, const openvdb::Coord* leaves,
                      detail::BatchTargets& targets);

  std::array<Bin, kSightBins> mBins;
  openvdb::Int32Grid::Ptr mBinMask;  ///< per voxel, bit b set where bin b holds terms
  double mVoxelSize;
  DataWindow mWindow;
  double mPositionVariance;
  std::size_t mGrainSize;
  openvdb::Int32 mSlabBegin = std::numeric_limits<openvdb::Int32>::min();
  openvdb::Int32 mSlabEnd = std::numeric_limits<openvdb::Int32>::max();
  std::size_t mMapCount = 0;
  std::size_t mEvaluations = 0;
};

class DataTermGrids::Sampler {
 public:
  explicit Sampler(const DataTermGrids& grids);
  DataTerms facingTerms(const openvdb::Vec3d& x, const openvdb::Vec3d& normal);
  double weight(const openvdb::Vec3d& x) { return allTerms(x).weight; }
  double readings(const openvdb::Vec3d& x) { return allTerms(x).readings; }

 private:
  template <typename TreeT>
  using Accessor = openvdb::tree::ValueAccessor<const TreeT, false>;
  /// The accessors of one bin's grids.
  struct BinAccess {
    explicit BinAccess(const Bin& bin);
    Accessor<openvdb::FloatTree> g, weight;
    Accessor<openvdb::Vec3fTree> gradient, sight;
    Accessor<openvdb::FloatTree> leafWeight, leafWindows;
  };
  /// Bin b's accessors, made the first time the bin is asked.
  BinAccess& bin(int b);
  /// Calls visit(bin, b, corners, masks) for each bin b with a term at one of
  /// the eight voxels around x (`corners`, with their trilinear weights; each
  /// voxel's bins in `masks`, bit b: bin b), in bin order: another bin's terms
  /// are 0 at all eight.
  template <typename Visit>
  void forEachBinAround(const openvdb::Vec3d& x, const Visit& visit);
  /// Weight and readings at x over all bins (g is left 0).
  DataTerms allTerms(const openvdb::Vec3d& x);

  const DataTermGrids* mGrids;
  Accessor<openvdb::Int32Tree> mMask;
  std::array<std::optional<BinAccess>, kSightBins> mBins;
};

namespace detail {
template <typename T, typename = void>
struct HasSampler : std::false_type {};
template <typename T>
struct HasSampler<T, std::void_t<decltype(std::declval<const T&>().sampler())>> : std::true_type {};
template <typename T, typename = void>
struct HasTermsTest : std::false_type {};
template <typename T>
struct HasTermsTest<T, std::void_t<decltype(std::declval<const T&>().mayHaveTermsIn(openvdb::BBoxd()))>>
    : std::true_type {};
}  // namespace detail

/// A data term's queries (facingTerms, weight, readings) for one task, point
/// after point of a leaf node: the term's own sampler() where it has one
/// (DataTermGrids::Sampler), the term itself otherwise (ForceField).
template <typename Field>
decltype(auto) samplerOf(const Field& field) {
  if constexpr (detail::HasSampler<Field>::value) return field.sampler();
  else return field;  // a reference: no copy
}

/// False only if `field` can tell that no term reaches any point of the world
/// box `world` (DataTermGrids::mayHaveTermsIn); true for a data term that
/// cannot tell (ForceField).
template <typename Field>
bool mayHaveTermsIn(const Field& field, const openvdb::BBoxd& world) {
  if constexpr (detail::HasTermsTest<Field>::value) return field.mayHaveTermsIn(world);
  else return true;
}

}  // namespace levelfuse
