// levelfuse: one slab of a sparse field cut along x, for processes that share
// a field's evolution (SlabTeam.h; the MPI ranks of mpi/RankTeam.h).
//
// The field is cut along x at leaf-node boundaries into slabs. A slab keeps
// the leaves it owns and, as ghosts, its neighbours' leaves in the one column
// of leaf nodes beside each of its faces. A step of the whole field is, on
// every slab at once:
//   1. refreshGhosts: each slab sends its leaves beside each neighbour
//      (ghostsFor) and takes theirs in place of its ghosts (acceptGhosts);
//   2. computeRates: the rates at its points, ghosts included; the largest
//      over its own points is combined across slabs (the maximum);
//   3. applyRates under the common time step; the tallies of the slabs add
//      up (StepTally.h) to the report of the whole field's step.
// Every slab steps its ghosts as well, so its own leaves see the neighbours'
// points exactly as the whole field would.
//
// Why one column of ghosts suffices: a step reads at most 3 + N voxels across
// (the rates' stencil, the conflict check and the replacement of leaving
// points one voxel each, and one for each of the N passes of the layer rule).
// What goes wrong at the outer face of the ghosts, beyond which the slab has
// no leaves, so reaches at most 6 voxels (N <= 3) into them, never the slab's
// own leaves 8 voxels in, and the next step starts from fresh ghosts. The
// slabs' own leaves are then bit-identical to the whole field's (tested).
#pragma once

#include <levelfuse/levelset/LeafNodeWidth.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/StepTally.h>

#include <openvdb/openvdb.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse {

namespace detail {
struct SparseFieldState;
}

/// The x voxel indices a slab owns, [begin, end), at leaf-node boundaries
/// (multiples of 8). The first slab begins, and the last ends, at infinity.
struct SlabBounds {
  static constexpr openvdb::Int32 kUnbounded = std::numeric_limits<openvdb::Int32>::max();
  openvdb::Int32 begin = -kUnbounded;
  openvdb::Int32 end = kUnbounded;

  /// Whether a slab lies below (at lower x), and above, this one.
  bool hasLower() const { return begin != -kUnbounded; }
  bool hasHigher() const { return end != kUnbounded; }
  /// Whether x (a voxel or leaf origin) lies in the slab.
  bool contains(openvdb::Int32 x) const { return x >= begin && x < end; }
};

/// Leaf nodes per column of leaf nodes of `tree` within `within` (all, by
/// default): the x origin of each column that has any, and how many it has
/// (balancedSlabs' input).
std::vector<std::pair<openvdb::Int32, std::size_t>> leafColumns(const openvdb::FloatTree& tree,
                                                                 const SlabBounds& within = {});

/// The same slab on a grid of half the voxel size (refineLevelSet): its bounds doubled.
SlabBounds onFinerGrid(const SlabBounds& bounds);

/// Leaves of a slab with their layers, packed as bytes for another process.
using PackedLeaves = std::vector<std::uint8_t>;

namespace detail {
/// Appends the `bytes` bytes at `data` to `out`: how every packing of leaves writes.
inline void appendBytes(PackedLeaves& out, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const std::uint8_t*>(data);
  out.insert(out.end(), p, p + bytes);
}
}  // namespace detail

/// The neighbour a slab exchanges ghosts with: lower x or higher x.
enum class SlabSide { kLower, kHigher };

class SlabField {
 public:
  /// The slab `bounds` of the sparse field fromLevelSet would build from
  /// `levelSet`, with its ghosts. `levelSet` needs to cover only the slab and
  /// its ghosts, plus one voxel. A slab the surface does not reach is empty.
  static SlabField fromLevelSet(const openvdb::FloatGrid& levelSet, const SlabBounds& bounds,
                                const SparseFieldOptions& options = {});
  /// The same, letting go of `levelSet` as soon as it has been read
  /// (SparseField::fromLevelSet).
  static SlabField fromLevelSet(openvdb::FloatGrid::Ptr&& levelSet, const SlabBounds& bounds,
                                const SparseFieldOptions& options = {});

  /// The slab `bounds` of `whole`, with its ghosts: the leaves, values and
  /// layers are copied as they are.
  static SlabField fromField(const SparseField& whole, const SlabBounds& bounds);

  SlabField(SlabField&&) noexcept;
  SlabField& operator=(SlabField&&) noexcept;
  ~SlabField();

  /// The slab's leaves beside its `side` neighbour, for that neighbour's ghosts.
  PackedLeaves ghostsFor(SlabSide side) const;
  /// Takes the `side` neighbour's leaves (its ghostsFor) in place of the ghosts on that side.
  void acceptGhosts(SlabSide side, const PackedLeaves& leaves);

  /// Phase 1 of a step: d psi/dt at every point, ghosts included. Returns
  /// the largest |d psi/dt| over the slab's own points. Explicitly
  /// instantiated for the speeds of SpeedTerms.h; include SlabFieldStep.h for
  /// a speed of your own.
  template <typename Speed>
  double computeRates(const Speed& speed);
  /// The time step for the largest speed over all slabs (SparseField::step's rule).
  double timeStep(double maxSpeed, double curvatureWeight, double stiffness, double maxDt) const;
  /// Phase 2: moves every point by dt times its rate and rebuilds the layers.
  /// Returns the tally of the slab's own leaves.
  StepTally applyRates(double dt, double maxSpeed);

  /// The slab's leaves and ghosts as an OpenVDB level set (SparseField::
  /// toLevelSet), to refine the slab for the next grid. With fresh ghosts
  /// (acceptGhosts after the last step), its values are the whole field's
  /// except within 2 voxels of the ghosts' outer faces; it has no leaves
  /// beyond them. The tiles beside its leaves take the side of the leaf
  /// voxels next to them.
  openvdb::FloatGrid::Ptr toLevelSet(double halfWidth = 3.0, const std::string& name = "surface") const&;
  /// The same, the slab let go as it is made: its values become the level
  /// set's, not a copy (std::move(slab).toLevelSet()).
  openvdb::FloatGrid::Ptr toLevelSet(double halfWidth = 3.0, const std::string& name = "surface") &&;

  /// The slab's own leaves, packed, for assembling the whole field.
  PackedLeaves ownedLeaves() const;
  /// The whole sparse field from every slab's ownedLeaves (in any order),
  /// each let go once its leaves are in. `levelSet` gives the transform and
  /// name, as it did to fromLevelSet.
  static SparseField assemble(std::vector<PackedLeaves> slabs, const openvdb::FloatGrid& levelSet,
                              const SparseFieldOptions& options = {});

  const SlabBounds& bounds() const { return mBounds; }
  /// Values of the slab's leaves and ghosts.
  const openvdb::FloatGrid& grid() const;
  double voxelSize() const;
  const SparseFieldOptions& options() const;
  /// Counts of the slab's own leaves; the bytes hold its ghosts too.
  SparseFieldStats stats() const;

 private:
  SlabField(std::unique_ptr<detail::SparseFieldState> state, const SlabBounds& bounds);
  std::unique_ptr<detail::SparseFieldState> mState;
  SlabBounds mBounds;
};

/// Cuts x at leaf-node boundaries into `count` slabs holding about the same
/// number of leaf nodes. `columns` holds, for each column of leaf nodes that
/// has any (its x origin, a multiple of `leafWidth` voxels), how many it has,
/// in any order; a coarser grid's columns may stand for the field's own.
/// Throws std::invalid_argument if there are fewer columns than slabs.
std::vector<SlabBounds> balancedSlabs(const std::vector<std::pair<openvdb::Int32, std::size_t>>& columns,
                                      int count, openvdb::Int32 leafWidth = kLeafNodeWidth);

}  // namespace levelfuse
