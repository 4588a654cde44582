// The eight voxels around a point as the data term's sampler reads them: a
// grid's values at the corners (from the one leaf that holds all eight where
// one does) are the values its accessor gives voxel by voxel, also where the
// cell crosses one, two or three faces of a leaf, and where a corner lies in a
// tile or the background.

#include "../../src/scan/CellCorners.h"

#include <gtest/gtest.h>

#include <openvdb/openvdb.h>

namespace levelfuse {
namespace {

using openvdb::Coord;
using openvdb::Vec3d;

constexpr double kVoxel = 0.5;

/// A value no two voxels of the test share.
float valueAt(const Coord& ijk) { return static_cast<float>(ijk.x() * 10007 + ijk.y() * 101 + ijk.z()) + 0.25f; }

/// Leaves around the origin with a value per voxel, one leaf left out (the
/// background there) and one a tile of its own value.
openvdb::FloatGrid::Ptr gridWithLeavesTilesAndBackground() {
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(-7.0f);
  openvdb::FloatGrid::Accessor acc = grid->getAccessor();
  for (int x = -16; x < 16; ++x)
    for (int y = -16; y < 16; ++y)
      for (int z = -16; z < 16; ++z) {
        const Coord ijk(x, y, z);
        if (ijk.x() >= 0 && ijk.x() < 8 && ijk.y() < 0 && ijk.y() >= -8 && ijk.z() >= 0 && ijk.z() < 8) continue;
        acc.setValue(ijk, valueAt(ijk));
      }
  grid->tree().addTile(1, Coord(-8, -8, -8), 3.5f, true);  // the leaf at (-8, -8, -8) becomes a tile
  return grid;
}

/// Every cell whose lowest corner lies in the 4 x 4 x 4 voxels around `centre`.
template <typename Visit>
void forEachCellAround(const Coord& centre, const Visit& visit) {
  for (int x = -2; x < 2; ++x)
    for (int y = -2; y < 2; ++y)
      for (int z = -2; z < 2; ++z) {
        const Vec3d inside(0.3, 0.55, 0.8);  // a point strictly inside the cell
        visit((centre.offsetBy(x, y, z).asVec3d() + inside) * kVoxel);
      }
}

TEST(CellCorners, EachCornersValueIsTheAccessorsAlsoAcrossTheFacesOfLeaves) {
  const openvdb::FloatGrid::Ptr grid = gridWithLeavesTilesAndBackground();
  openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc(grid->tree());
  openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> check(grid->tree());
  int crossings[4] = {0, 0, 0, 0};  // cells by the number of leaf faces they cross
  // Around a corner of eight leaves: one missing, one a tile.
  forEachCellAround(Coord(0, 0, 0), [&](const Vec3d& x) {
    const detail::CellCorners c = detail::cellCornersAround(x, kVoxel);
    const detail::CornerValues<decltype(acc)> values(acc, c);
    int faces = 0;
    for (int axis = 0; axis < 3; ++axis) faces += (c.ijk[0][axis] & 7) == 7;
    ++crossings[faces];
    EXPECT_EQ(c.oneLeaf, faces == 0);
    for (int k = 0; k < 8; ++k) EXPECT_EQ(values[k], check.getValue(c.ijk[k])) << "corner " << k << " at " << c.ijk[k];
  });
  for (int faces = 0; faces < 4; ++faces) EXPECT_GT(crossings[faces], 0) << faces << " faces";
}

TEST(CellCorners, EachCornersLeafValueIsTheValueOfItsLeafsBlock) {
  // One voxel per leaf: the block of leaf (i, j, k) holds a value of its own.
  openvdb::FloatGrid::Ptr blocks = openvdb::FloatGrid::create(0.0f);
  for (int x = -2; x < 2; ++x)
    for (int y = -2; y < 2; ++y)
      for (int z = -2; z < 2; ++z)
        if (x != 0 || y != -1 || z != 0) blocks->tree().setValue(Coord(x, y, z), valueAt(Coord(x, y, z)));
  openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc(blocks->tree());
  forEachCellAround(Coord(0, 0, 0), [&](const Vec3d& x) {
    const detail::CellCorners c = detail::cellCornersAround(x, kVoxel);
    const detail::CornerLeafValues<decltype(acc)> values(acc, c);
    for (int k = 0; k < 8; ++k)
      EXPECT_EQ(values[k], blocks->tree().getValue(detail::leafBlockOf(c.ijk[k]))) << "corner " << k;
  });
}

}  // namespace
}  // namespace levelfuse
