// levelfuse: narrow-band sampling of signed distance functions.

#include <levelfuse/levelset/Background.h>
#include <levelfuse/levelset/LevelSetFromFunction.h>

#include <openvdb/tools/SignedFloodFill.h>

#include <levelfuse/core/Parallel.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

namespace levelfuse {

openvdb::FloatGrid::Ptr levelSetFromFunction(const std::function<double(const openvdb::Vec3d&)>& signedDistance,
                                             const openvdb::BBoxd& bounds, double voxelSize, double halfWidth,
                                             const std::string& name) {
  using LeafT = openvdb::FloatTree::LeafNodeType;
  if (!(voxelSize > 0.0) || !(halfWidth >= 1.0))
    throw std::invalid_argument("levelSetFromFunction: the voxel size must be positive and the half-width >= 1");
  const float width = levelSetBackground(halfWidth, voxelSize);
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(width);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->setName(name);
  const openvdb::math::Transform& xform = grid->transform();

  const openvdb::Coord lo = openvdb::Coord::floor(xform.worldToIndex(bounds.min())) & ~int(LeafT::DIM - 1);
  const openvdb::Coord hi = openvdb::Coord::ceil(xform.worldToIndex(bounds.max()));
  std::vector<openvdb::Coord> origins;
  for (int x = lo.x(); x <= hi.x(); x += LeafT::DIM)
    for (int y = lo.y(); y <= hi.y(); y += LeafT::DIM)
      for (int z = lo.z(); z <= hi.z(); z += LeafT::DIM) origins.emplace_back(x, y, z);

  // A leaf can hold band voxels only if the distance at its centre is within
  // its half-diagonal plus the band (the function is 1-Lipschitz).
  const double reach = (0.5 * std::sqrt(3.0) * (LeafT::DIM - 1) + halfWidth) * voxelSize;
  std::vector<std::unique_ptr<LeafT>> leaves(origins.size());
  parallelFor(origins.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i != end; ++i) {
      const openvdb::Vec3d centre = xform.indexToWorld(origins[i].asVec3d() + openvdb::Vec3d(0.5 * (LeafT::DIM - 1)));
      if (std::fabs(signedDistance(centre)) > reach) continue;
      auto leaf = std::make_unique<LeafT>(origins[i], width);
      bool any = false;
      for (openvdb::Index o = 0; o < LeafT::SIZE; ++o) {
        const float d = static_cast<float>(signedDistance(xform.indexToWorld(leaf->offsetToGlobalCoord(o))));
        if (std::fabs(d) < width) {
          leaf->setValueOn(o, d);
          any = true;
        } else {
          leaf->setValueOff(o, d < 0.0f ? -width : width);
        }
      }
      if (any) leaves[i] = std::move(leaf);
    }
  });
  for (auto& leaf : leaves)
    if (leaf) grid->tree().addLeaf(leaf.release());
  openvdb::tools::signedFloodFill(grid->tree());
  return grid;
}

}  // namespace levelfuse
