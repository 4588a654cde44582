// levelfuse: refining a level set to half the voxel size.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/levelset/Background.h>
#include <levelfuse/levelset/Refine.h>
#include <levelfuse/levelset/RequireLevelSet.h>

#include <openvdb/tools/Interpolation.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

namespace levelfuse {

namespace {

/// 2 ijk: multiplied, not shifted, as a left shift of a negative coordinate is undefined.
openvdb::Coord twice(const openvdb::Coord& ijk) { return openvdb::Coord(2 * ijk.x(), 2 * ijk.y(), 2 * ijk.z()); }

}  // namespace

openvdb::FloatGrid::Ptr refineLevelSet(const openvdb::FloatGrid& levelSet, double halfWidth) {
  using LeafT = openvdb::FloatTree::LeafNodeType;
  requireLevelSet(levelSet, "refineLevelSet");
  if (!(halfWidth >= 1.0)) throw std::invalid_argument("refineLevelSet: the half-width must be at least one voxel");

  openvdb::math::Transform::Ptr fineTransform = levelSet.transform().copy();
  fineTransform->preScale(0.5);  // fine index j lies at coarse index j / 2
  const float width = levelSetBackground(halfWidth, fineTransform->voxelSize()[0]);
  openvdb::FloatGrid::Ptr fine = openvdb::FloatGrid::create(width);
  fine->setTransform(fineTransform);
  fine->setGridClass(openvdb::GRID_LEVEL_SET);
  fine->setName(levelSet.getName());

  // Inside tiles cover twice the index range on the fine grid.
  for (auto tile = levelSet.tree().cbeginValueAll(); tile; ++tile) {
    if (tile.isVoxelValue() || !(*tile < 0.0f)) continue;
    openvdb::CoordBBox box;
    tile.getBoundingBox(box);
    fine->tree().fill(openvdb::CoordBBox(twice(box.min()), twice(box.max()) + openvdb::Coord(1)), -width, false);
  }

  // Each coarse leaf becomes the eight fine leaves over the same space.
  std::vector<const LeafT*> coarse;
  levelSet.tree().getNodes(coarse);
  std::vector<std::unique_ptr<LeafT>> leaves(coarse.size() * 8);
  parallelFor(coarse.size(), 1, [&](std::size_t begin, std::size_t end) {
    openvdb::FloatGrid::ConstAccessor acc = levelSet.getConstAccessor();
    for (std::size_t i = begin; i < end; ++i)
      for (int child = 0; child < 8; ++child) {
        const int dim = static_cast<int>(LeafT::DIM);
        const openvdb::Coord origin =
            twice(coarse[i]->origin()) + openvdb::Coord((child & 1) * dim, ((child >> 1) & 1) * dim, (child >> 2) * dim);
        auto leaf = std::make_unique<LeafT>(origin, width);
        for (openvdb::Index o = 0; o < LeafT::SIZE; ++o) {
          const float v = openvdb::tools::BoxSampler::sample(acc, leaf->offsetToGlobalCoord(o).asVec3d() * 0.5);
          if (std::fabs(v) < width) leaf->setValueOn(o, v);
          else leaf->setValueOff(o, v < 0.0f ? -width : width);
        }
        leaves[8 * i + static_cast<std::size_t>(child)] = std::move(leaf);
      }
  });
  for (auto& leaf : leaves) fine->tree().addLeaf(leaf.release());
  return fine;
}

}  // namespace levelfuse
