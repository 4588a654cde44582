// levelfuse: the dense-field reference.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/levelset/DenseField.h>
#include <levelfuse/levelset/RequireLevelSet.h>

#include <openvdb/tools/SignedFloodFill.h>

#include <cmath>
#include <stdexcept>
#include <utility>

namespace levelfuse {

DenseField::DenseField(const openvdb::CoordBBox& box, openvdb::math::Transform::Ptr transform,
                       const std::function<double(const openvdb::Vec3d&)>& signedDistance,
                       const DenseFieldOptions& options)
    : mBox(box), mDim(box.dim()), mTransform(std::move(transform)), mOptions(options) {
  if (box.empty()) throw std::invalid_argument("DenseField: the box is empty");
  if (!mTransform || !mTransform->hasUniformScale())
    throw std::invalid_argument("DenseField: the transform must have uniform (cubic) voxels");
  mDx = mTransform->voxelSize()[0];
  mValues.resize(box.volume());
  mRates.resize(box.volume());
  parallelFor(static_cast<std::size_t>(mDim.x()), 1, [&](std::size_t begin, std::size_t end) {
    for (int x = box.min().x() + int(begin); x != box.min().x() + int(end); ++x)
      for (int y = box.min().y(); y <= box.max().y(); ++y)
        for (int z = box.min().z(); z <= box.max().z(); ++z) {
          const openvdb::Coord ijk(x, y, z);
          mValues[index(ijk)] = static_cast<float>(signedDistance(mTransform->indexToWorld(ijk)));
        }
  });
}

DenseField DenseField::fromLevelSet(const openvdb::FloatGrid& levelSet, const openvdb::CoordBBox& box,
                                    const DenseFieldOptions& options) {
  requireLevelSet(levelSet, "DenseField::fromLevelSet");
  const openvdb::math::Transform& xform = levelSet.transform();
  // Sampled at grid points only, so the world-to-index round trip is exact.
  return DenseField(
      box, xform.copy(),
      [&](const openvdb::Vec3d& p) {
        return levelSet.tree().getValue(openvdb::Coord::round(xform.worldToIndex(p)));
      },
      options);
}

openvdb::FloatGrid::Ptr DenseField::toGrid(double bandWidth) const {
  const float width = static_cast<float>(bandWidth * mDx);
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(width);
  grid->setTransform(mTransform->copy());
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  openvdb::FloatGrid::Accessor acc = grid->getAccessor();
  for (int x = mBox.min().x(); x <= mBox.max().x(); ++x)
    for (int y = mBox.min().y(); y <= mBox.max().y(); ++y)
      for (int z = mBox.min().z(); z <= mBox.max().z(); ++z) {
        const openvdb::Coord ijk(x, y, z);
        const float v = mValues[index(ijk)];
        if (std::fabs(v) < width) acc.setValueOn(ijk, v);
      }
  openvdb::tools::signedFloodFill(grid->tree());
  return grid;
}

}  // namespace levelfuse
