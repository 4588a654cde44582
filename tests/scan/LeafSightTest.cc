// What a range map says of a whole leaf node at once (detail::leafSight):
// never other than what it says of each voxel.

#include "../../src/scan/LeavesReached.h"

#include <levelfuse/scan/RangeMap.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Coord;
using openvdb::Vec3d;
using Sight = RangeMap::Sight;

/// A camera at (0.05, -0.03, -0.1), turned a little about y, looking at a wall
/// 2 m away with a box 0.5 m in front of it and a hole without readings.
RangeMap wallWithABox() {
  const int width = 80, height = 60;
  std::vector<float> depths(static_cast<std::size_t>(width) * height, 2.0f);
  for (int v = 20; v < 40; ++v)
    for (int u = 30; u < 50; ++u) depths[static_cast<std::size_t>(v) * width + u] = 1.5f;
  for (int v = 5; v < 12; ++v)
    for (int u = 60; u < 70; ++u) depths[static_cast<std::size_t>(v) * width + u] = std::numeric_limits<float>::quiet_NaN();
  openvdb::math::Mat4d cameraToWorld = openvdb::math::Mat4d::identity();
  cameraToWorld.setToRotation(openvdb::math::Y_AXIS, 0.2);
  cameraToWorld.setTranslation(Vec3d(0.05, -0.03, -0.1));
  return RangeMap::pinhole(width, height, depths, PinholeProjection{60.0, 60.0, 39.5, 29.5}, cameraToWorld, 0.002,
                           "wall");
}

/// Parallel rays along +z over a 2 x 2 patch, readings on the plane z = 1 + 0.2 x.
RangeMap tiltedPlaneAlongZ() {
  const int size = 50;
  const double pixel = 0.04;
  std::vector<float> readings(static_cast<std::size_t>(size) * size);
  for (int v = 0; v < size; ++v)
    for (int u = 0; u < size; ++u) readings[static_cast<std::size_t>(v) * size + u] = 1.0f + 0.2f * float(u * pixel - 1.0);
  return RangeMap::orthographic(size, size, readings, OrthographicProjection{pixel, openvdb::math::Vec2d(-1.0, -1.0)},
                                openvdb::math::Mat4d::identity(), 0.002, "plane");
}

TEST(LeafSight, WhatALeafIsToldEveryVoxelIsToo) {
  const double voxel = 0.02, margin = 0.03;
  for (const RangeMap& map : {wallWithABox(), tiltedPlaneAlongZ()}) {
    std::array<std::size_t, 4> leaves{};  // per Sight
    for (int x = -96; x <= 96; x += 8)
      for (int y = -96; y <= 96; y += 8)
        for (int z = -16; z <= 160; z += 8) {
          const Coord origin(x, y, z);
          const Sight whole = detail::leafSight(map, origin, voxel, margin);
          ++leaves[static_cast<std::size_t>(whole)];
          if (whole == Sight::kUnknown) continue;
          for (int i = 0; i < 8; ++i)
            for (int j = 0; j < 8; ++j)
              for (int k = 0; k < 8; ++k) {
                const Vec3d p = origin.offsetBy(i, j, k).asVec3d() * voxel;
                ASSERT_EQ(map.sight(p, margin), whole) << map.name() << " leaf " << origin << " voxel " << p;
              }
        }
    // The shortcut answers for most leaves: in front, behind and beside.
    EXPECT_GT(leaves[static_cast<std::size_t>(Sight::kEmpty)], 100u);
    EXPECT_GT(leaves[static_cast<std::size_t>(Sight::kBehind)], 100u);
    EXPECT_GT(leaves[static_cast<std::size_t>(Sight::kOutside)], 100u);
  }
}

}  // namespace
}  // namespace levelfuse
