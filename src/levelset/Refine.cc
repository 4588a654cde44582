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

using LeafT = openvdb::FloatTree::LeafNodeType;

/// 2 ijk: multiplied, not shifted, as a left shift of a negative coordinate is undefined.
openvdb::Coord twice(const openvdb::Coord& ijk) { return openvdb::Coord(2 * ijk.x(), 2 * ijk.y(), 2 * ijk.z()); }

/// The fine value at fine index `ijk`: the coarse level set sampled there.
float fineValue(const openvdb::FloatGrid::ConstAccessor& coarse, const openvdb::Coord& ijk) {
  return openvdb::tools::BoxSampler::sample(coarse, ijk.asVec3d() * 0.5);
}

/// floor(v / 2), also for negative v.
openvdb::Int32 floorHalf(openvdb::Int32 v) { return v >= 0 ? v / 2 : -((1 - v) / 2); }

/// Whether every coarse value the fine leaf at `origin`, and the fine voxels
/// one beyond it, are sampled from lies on one side: then so do they.
bool onOneSide(const openvdb::FloatGrid::ConstAccessor& coarse, const openvdb::Coord& origin, bool inside) {
  const openvdb::Int32 dim = static_cast<openvdb::Int32>(LeafT::DIM);
  const openvdb::Coord lo(floorHalf(origin.x() - 1), floorHalf(origin.y() - 1), floorHalf(origin.z() - 1));
  const openvdb::Coord hi(floorHalf(origin.x() + dim) + 1, floorHalf(origin.y() + dim) + 1,
                          floorHalf(origin.z() + dim) + 1);
  for (openvdb::Int32 i = lo.x(); i <= hi.x(); ++i)
    for (openvdb::Int32 j = lo.y(); j <= hi.y(); ++j)
      for (openvdb::Int32 k = lo.z(); k <= hi.z(); ++k)
        if ((coarse.getValue(openvdb::Coord(i, j, k)) < 0.0f) != inside) return false;
  return true;
}

/// A fine leaf node of the refined level set, or a tile of its side where no
/// voxel of it or next to it lies in the band or across the surface: such a
/// leaf, all +-width, reads as the tile does, and no zero crossing touches it.
struct FineLeaf {
  openvdb::Coord origin;
  std::unique_ptr<LeafT> leaf;  ///< null for a tile
  bool inside = false;
};

FineLeaf fineLeaf(const openvdb::FloatGrid::ConstAccessor& coarse, const openvdb::Coord& origin, float width) {
  FineLeaf out{origin, std::make_unique<LeafT>(origin, width), false};
  for (openvdb::Index o = 0; o < LeafT::SIZE; ++o) {
    const float v = fineValue(coarse, out.leaf->offsetToGlobalCoord(o));
    if (std::fabs(v) < width) out.leaf->setValueOn(o, v);
    else out.leaf->setValueOff(o, v < 0.0f ? -width : width);
  }
  out.inside = out.leaf->getFirstValue() < 0.0f;
  if (out.leaf->isEmpty() && onOneSide(coarse, origin, out.inside)) out.leaf.reset();
  return out;
}

}  // namespace

openvdb::FloatGrid::Ptr refineLevelSet(const openvdb::FloatGrid& levelSet, double halfWidth) {
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

  // Each coarse leaf becomes the eight fine leaves over the same space; those
  // the band does not reach become tiles of their side, as a leaf of one
  // value beyond the band reads the same.
  std::vector<const LeafT*> coarse;
  levelSet.tree().getNodes(coarse);
  std::vector<FineLeaf> leaves(coarse.size() * 8);
  parallelFor(coarse.size(), 1, [&](std::size_t begin, std::size_t end) {
    openvdb::FloatGrid::ConstAccessor acc = levelSet.getConstAccessor();
    for (std::size_t i = begin; i < end; ++i)
      for (int child = 0; child < 8; ++child) {
        const int dim = static_cast<int>(LeafT::DIM);
        const openvdb::Coord origin =
            twice(coarse[i]->origin()) + openvdb::Coord((child & 1) * dim, ((child >> 1) & 1) * dim, (child >> 2) * dim);
        leaves[8 * i + static_cast<std::size_t>(child)] = fineLeaf(acc, origin, width);
      }
  });
  for (FineLeaf& made : leaves) {
    if (made.leaf) fine->tree().addLeaf(made.leaf.release());
    else fine->tree().addTile(1, made.origin, made.inside ? -width : width, false);
  }
  return fine;
}

}  // namespace levelfuse
