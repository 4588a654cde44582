// The leaves' sign masks and zero crossings (detail/LeafSigns.h) against
// the voxel-by-voxel definition, on grids with leaves, tiles and background.

#include <levelfuse/levelset/detail/LeafSigns.h>

#include <gtest/gtest.h>

#include <openvdb/openvdb.h>

#include <random>

namespace levelfuse {
namespace {

using openvdb::Coord;
using LeafT = openvdb::FloatTree::LeafNodeType;

/// A grid of random values of either sign in a few leaves, beside an inside
/// tile of a leaf's size, over a positive background.
openvdb::FloatGrid::Ptr randomSigns(unsigned seed) {
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(3.0f);
  grid->tree().addTile(1, Coord(0, 0, 128), -3.0f, false);
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  std::uniform_int_distribution<int> zeroes(0, 19);
  openvdb::FloatGrid::Accessor acc = grid->getAccessor();
  for (const Coord& origin : {Coord(0, 0, 0), Coord(8, 0, 0), Coord(0, 8, 0), Coord(0, 0, 120), Coord(0, 0, 8),
                              Coord(-8, -8, -8)})
    for (openvdb::Index o = 0; o < LeafT::SIZE; ++o)
      acc.setValueOn(origin + LeafT::offsetToLocalCoord(o), zeroes(random) == 0 ? 0.0f : value(random));
  return grid;
}

TEST(LeafSigns, ZeroCrossingsAreTheVoxelsWithAFaceNeighbourOfTheOtherSign) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const openvdb::FloatGrid::Ptr grid = randomSigns(seed);
    const openvdb::FloatGrid::ConstAccessor acc = grid->getConstAccessor();
    std::size_t crossings = 0, beyondTheLeaf = 0;
    for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) {
      const detail::LeafMask negative = detail::negativeVoxels(*leaf);
      const detail::LeafMask crossing = detail::zeroCrossingVoxels(acc, *leaf);
      for (openvdb::Index o = 0; o < LeafT::SIZE; ++o) {
        const Coord ijk = leaf->offsetToGlobalCoord(o), local = LeafT::offsetToLocalCoord(o);
        const bool inside = acc.getValue(ijk) < 0.0f;
        EXPECT_EQ(negative.isOn(o), inside) << ijk;
        bool expected = false;
        for (const auto& e : detail::kFaceOffset) {
          const float beside = acc.getValue(ijk.offsetBy(e[0], e[1], e[2]));
          EXPECT_EQ(detail::valueBeside(acc, *leaf, local, e), beside) << ijk;
          expected = expected || (beside < 0.0f) != inside;
        }
        EXPECT_EQ(crossing.isOn(o), expected) << ijk;
        crossings += expected;
        if (expected && (local.x() % 7 == 0 || local.y() % 7 == 0 || local.z() % 7 == 0)) ++beyondTheLeaf;
      }
    }
    EXPECT_GT(crossings, 1000u);   // random signs cross almost everywhere
    EXPECT_GT(beyondTheLeaf, 100u);  // on the leaves' faces too
  }
}

TEST(LeafSigns, AUniformLeafCrossesOnlyWhereItsNeighboursDiffer) {
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(3.0f);
  openvdb::FloatGrid::Accessor acc = grid->getAccessor();
  for (openvdb::Index o = 0; o < LeafT::SIZE; ++o) acc.setValueOn(LeafT::offsetToLocalCoord(o), -1.0f);
  const LeafT& leaf = *grid->tree().probeConstLeaf(Coord(0));
  // Inside, against the positive background on every side: its faces cross.
  const detail::LeafMask crossing = detail::zeroCrossingVoxels(grid->getConstAccessor(), leaf);
  EXPECT_EQ(crossing.countOn(), LeafT::SIZE - 6u * 6u * 6u);
  // Within an inside tile on every side: nothing crosses.
  openvdb::FloatGrid::Ptr within = openvdb::FloatGrid::create(3.0f);
  within->tree().addTile(2, Coord(0), -3.0f, false);  // 128^3 voxels
  openvdb::FloatGrid::Accessor inTile = within->getAccessor();
  inTile.setValueOn(Coord(8, 8, 8), -1.0f);
  const LeafT& touched = *within->tree().probeConstLeaf(Coord(8));
  EXPECT_TRUE(detail::zeroCrossingVoxels(within->getConstAccessor(), touched).isOff());
}

}  // namespace
}  // namespace levelfuse
