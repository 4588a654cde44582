// levelfuse: the dense-field reference (the "dense-field method" of section 5.1).
//
// The same numerical scheme as SparseField (the same stencils, speeds and time
// step rules), applied to every voxel of a dense box with no layers and no
// active set. It exists to hold the sparse field against: accuracy (Fig. 5),
// aliasing (Figs. 7-8) and cost (Table 1).
#pragma once

#include <levelfuse/levelset/SparseField.h>

#include <openvdb/openvdb.h>

#include <functional>
#include <limits>
#include <vector>

namespace levelfuse {

/// The dense field takes its time steps by the sparse field's rule
/// (stableTimeStep) with the same limits but one: its curvature term acts on
/// every voxel of the box, as diffusion in three dimensions, whose explicit
/// limit is 1/6 (the sparse field's active points see it within the surface,
/// in two: 1/4).
struct DenseFieldOptions {
  double maxStepChange = 0.45;            ///< largest change of a value in one step, in voxels
  double curvatureStepLimit = 1.0 / 6.0;  ///< dt <= this * dx^2 / beta
  double stiffnessStepLimit = 0.5;        ///< dt k <= this for a force of stiffness k
  std::size_t grainSize = 1;              ///< x slabs per task; 0 runs serially
};

class DenseField {
 public:
  /// Samples `signedDistance` (world units, negative inside) at every voxel of
  /// `box`, an index-space box of `transform`.
  DenseField(const openvdb::CoordBBox& box, openvdb::math::Transform::Ptr transform,
             const std::function<double(const openvdb::Vec3d&)>& signedDistance,
             const DenseFieldOptions& options = {});
  /// Copies a level set into `box`; voxels beyond its band hold its +-background.
  static DenseField fromLevelSet(const openvdb::FloatGrid& levelSet, const openvdb::CoordBBox& box,
                                 const DenseFieldOptions& options = {});

  /// Advances every voxel by one time step under `speed`; the time step is
  /// limited by the fastest voxel anywhere in the box (Eq. 32). The stencil is
  /// clamped at the box faces. Instantiated for the speeds of SpeedTerms.h;
  /// include DenseFieldStep.h for others.
  template <typename Speed>
  StepResult step(const Speed& speed, double maxDt = std::numeric_limits<double>::infinity());

  /// The values as an OpenVDB level set whose active voxels lie within
  /// `bandWidth` voxels of the surface.
  openvdb::FloatGrid::Ptr toGrid(double bandWidth = 3.0) const;

  float value(const openvdb::Coord& ijk) const { return mValues[index(ijk)]; }
  const openvdb::CoordBBox& box() const { return mBox; }
  const openvdb::math::Transform& transform() const { return *mTransform; }
  double voxelSize() const { return mDx; }
  std::size_t memoryBytes() const { return (mValues.capacity() + mRates.capacity()) * sizeof(float); }
  void setGrainSize(std::size_t grainSize) { mOptions.grainSize = grainSize; }

 private:
  std::size_t index(const openvdb::Coord& ijk) const {
    return (static_cast<std::size_t>(ijk.x() - mBox.min().x()) * mDim.y() +
            static_cast<std::size_t>(ijk.y() - mBox.min().y())) * mDim.z() +
           static_cast<std::size_t>(ijk.z() - mBox.min().z());
  }

  openvdb::CoordBBox mBox;
  openvdb::Coord mDim;
  openvdb::math::Transform::Ptr mTransform;
  DenseFieldOptions mOptions;
  double mDx = 1.0;
  std::vector<float> mValues, mRates;
};

}  // namespace levelfuse
