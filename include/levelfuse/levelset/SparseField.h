// levelfuse: the sparse-field level-set engine (Whitaker 1998, section 5).
//
// A SparseField owns an OpenVDB FloatGrid level set (negative inside, world
// units) together with its active set L0 and the layers L+-1 ... L+-N around
// it. The layers are bit masks stored with the value tree's leaf nodes, so the
// engine's memory grows with the surface, never with the bounding box. One
// step() updates the active values under a speed (see SpeedTerms.h), moves the
// points whose values leave [-1/2, 1/2] voxel to the neighbouring layers, and
// rebuilds the layers outward from L0. Every phase of a step is a
// bulk-synchronous parallel pass over leaf nodes: the result is bit-identical
// whatever the number of threads.
#pragma once

#include <levelfuse/levelset/SparseFieldOptions.h>
#include <levelfuse/levelset/SparseFieldStats.h>
#include <levelfuse/levelset/StepResult.h>

#include <openvdb/openvdb.h>

#include <cstddef>
#include <limits>
#include <memory>
#include <string>

namespace levelfuse {

namespace detail {
struct SparseFieldState;
}
struct InvariantReport;

class SparseField {
 public:
  /// Builds the active set and layers from an OpenVDB level set (any narrow-band
  /// width >= 1 voxel, e.g. from tools::createLevelSetSphere or meshToLevelSet).
  /// Throws std::invalid_argument, with a hint, for a grid that is not a level
  /// set, has non-uniform voxels, or holds non-finite values.
  static SparseField fromLevelSet(const openvdb::FloatGrid& levelSet,
                                  const SparseFieldOptions& options = {});
  /// The same, letting go of `levelSet` as soon as it has been read, before
  /// the layers are built (it is freed if this held its only reference).
  static SparseField fromLevelSet(openvdb::FloatGrid::Ptr&& levelSet, const SparseFieldOptions& options = {});

  /// Builds a level set from a binary inside/outside mask (active = inside):
  /// the surface runs halfway between inside and outside voxel centres, as for
  /// the paper's occupancy-grid initial models.
  static SparseField fromMask(const openvdb::MaskGrid& inside,
                              const SparseFieldOptions& options = {});

  SparseField(SparseField&&) noexcept;
  SparseField& operator=(SparseField&&) noexcept;
  SparseField(const SparseField&);
  SparseField& operator=(const SparseField&);
  ~SparseField();

  /// Advances the level set by one time step under `speed` (see SpeedTerms.h),
  /// never by more than `maxDt`. The step is limited so that no active value
  /// changes by maxStepChange voxels or more, and by the stability of the
  /// curvature term. Explicitly instantiated for the speeds of SpeedTerms.h;
  /// include SparseFieldStep.h to use a speed of your own.
  template <typename Speed>
  StepResult step(const Speed& speed, double maxDt = std::numeric_limits<double>::infinity());

  /// Advances by `duration` (several steps) unless `interrupt` returns true
  /// between steps. Returns the number of steps taken.
  template <typename Speed, typename Interrupt>
  std::size_t advance(const Speed& speed, double duration, Interrupt interrupt) {
    std::size_t steps = 0;
    for (double t = 0.0; t < duration && !interrupt(); ++steps) {
      const StepResult r = step(speed, duration - t);
      if (r.dt <= 0.0) break;
      t += r.dt;
    }
    return steps;
  }
  template <typename Speed>
  std::size_t advance(const Speed& speed, double duration) {
    return advance(speed, duration, [] { return false; });
  }

  /// The evolving values: active voxels are the layers, background (N + 1/2) dx.
  const openvdb::FloatGrid& grid() const;
  /// A standard OpenVDB level set: GRID_LEVEL_SET class, background and
  /// narrow-band half-width `halfWidth` voxels (layers past N are added with the
  /// sparse field's own rule), named `name`.
  openvdb::FloatGrid::Ptr toLevelSet(double halfWidth = 3.0, const std::string& name = "surface") const&;
  /// The same, the field let go as it is made: its values become the level
  /// set's, not a copy (std::move(field).toLevelSet()).
  openvdb::FloatGrid::Ptr toLevelSet(double halfWidth = 3.0, const std::string& name = "surface") &&;

  /// Layer of a voxel: 0 for the active set, +-i for L+-i, +-(N+1) outside the layers.
  int layerOf(const openvdb::Coord& ijk) const;
  int layers() const;
  double voxelSize() const;
  const SparseFieldOptions& options() const;
  void setGrainSize(std::size_t grainSize);
  SparseFieldStats stats() const;

 private:
  /// The invariant checker reads the engine's internals (Invariants.h).
  friend InvariantReport checkInvariants(const SparseField& field);
  /// Slabs assemble a whole field from their leaves (SlabField.h).
  friend class SlabField;
  const detail::SparseFieldState& state() const { return *mState; }

  explicit SparseField(std::unique_ptr<detail::SparseFieldState> state);
  std::unique_ptr<detail::SparseFieldState> mState;
};

}  // namespace levelfuse
