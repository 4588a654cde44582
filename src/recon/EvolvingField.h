// levelfuse: the field a reconstruction evolves on one grid: the whole
// field, or this process's slab of it when a team of processes shares the
// evolution (levelset/SlabTeam.h). Private to the reconstruction.
#pragma once

#include <levelfuse/levelset/SlabTeam.h>
#include <levelfuse/levelset/SparseField.h>

#include <openvdb/openvdb.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace levelfuse::detail {

class EvolvingField {
 public:
  /// The whole field, in this process.
  explicit EvolvingField(SparseField whole);
  /// This process's slab of `whole`, the coarsest grid's field, which every
  /// process of `team` has made alike: the field is cut into as many slabs as
  /// the team has processes, with about as many leaf nodes each. Each finer
  /// grid is cut afresh (refine).
  EvolvingField(const SparseField& whole, const SlabTeam& team);
  /// This process's slab of `team`'s field, cut before the field was made
  /// (from this process's slab of the data alone, recon/SharedData.h).
  EvolvingField(SlabField slab, const SlabTeam& team);

  EvolvingField(EvolvingField&&) noexcept;
  EvolvingField& operator=(EvolvingField&&) noexcept;
  ~EvolvingField();

  /// One step under `speed`: the whole field's report, on every process.
  template <typename Speed>
  StepResult step(const Speed& speed) {
    return mSlab ? stepSlab(*mSlab, speed, *mTeam) : mWhole->step(speed);
  }
  /// The values: the whole field's, or the slab's with its ghosts.
  const openvdb::FloatGrid& grid() const;
  /// Whether this process answers for the leaf at `origin` (all, for the whole field).
  bool owns(const openvdb::Coord& origin) const;
  /// The largest of every process's `value`.
  double largest(double value) const;
  /// The field resampled to half the voxel size (refineLevelSet) and built
  /// again with `engine`; on a team, the finer grid is cut afresh where its
  /// leaf nodes share out evenly, and this process takes its new slab
  /// (refineAcrossTeam).
  void refine(const SparseFieldOptions& engine);
  /// A level set and the weight grid made of it.
  struct Surface {
    openvdb::FloatGrid::Ptr levelSet, weight;
  };
  /// Makes a level set's weight grid (recon/SurfaceWeight.h).
  using Weigh = std::function<openvdb::FloatGrid::Ptr(const openvdb::FloatGrid&)>;
  /// The whole field as an OpenVDB level set (half-width 3, named `name`),
  /// with its weight grid, `weigh` of it: on a team, at its first process
  /// only (null on the others). The field is let go, its counts kept: the
  /// outputs made from the level set need the memory. On a team, each
  /// process makes its slab's leaves of the level set and weighs them (the
  /// data it reads are its slab's), and the first puts them together
  /// (LevelSetPieces.h): it never holds the whole field. With `inPieces`,
  /// every process of a team returns its slab's level set and weight
  /// instead, its neighbours' leaves beside its own (the voxels that normals
  /// at the slab's edge read), for the grids made from it; keepOwnPiece
  /// then cuts them down to the process's piece.
  Surface release(const std::string& name, const Weigh& weigh, bool inPieces = false);
  /// After release(name, true): `levelSet` becomes this process's piece of
  /// the whole level set (closeLevelSetPiece, described by
  /// describeLevelSetPiece), and `weight` and `colour` (either may be null)
  /// keep that piece's voxels alone. For the whole field, the one piece of one.
  void keepOwnPiece(openvdb::FloatGrid::Ptr& levelSet, openvdb::FloatGrid::Ptr& weight,
                    openvdb::Vec3fGrid::Ptr& colour) const;
  /// The whole field's counts; the bytes are this process's.
  SparseFieldStats stats() const;
  /// The leaf nodes this process answers for: its slab's own, or the whole field's.
  std::size_t ownLeafNodes() const;
  /// This process's slab of a team's field; none for the whole field.
  std::optional<SlabBounds> slabBounds() const;

 private:
  std::unique_ptr<SparseField> mWhole;
  std::unique_ptr<SlabField> mSlab;
  const SlabTeam* mTeam = nullptr;
  // What stats() and ownLeafNodes() said when the field was let go.
  SparseFieldStats mReleasedStats;
  std::size_t mReleasedOwnLeaves = 0;
  SlabBounds mReleasedBounds;  // the slab's, when it was let go
};

}  // namespace levelfuse::detail
