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

constexpr double kVoxel = 0.02, kMargin = 0.03;

/// What `map` says of the cubes of `dim` voxels a side over a box around its
/// readings (leafSight for leaves, cubeSight for the others), checked against
/// every voxel of every cube it speaks for at once; how many cubes got each answer.
std::array<std::size_t, 4> cubesTold(const RangeMap& map, int dim) {
  std::array<std::size_t, 4> cubes{};  // per Sight
  for (int x = -96; x <= 96; x += dim)
    for (int y = -96; y <= 96; y += dim)
      for (int z = -16; z <= 160; z += dim) {
        const Coord origin(x, y, z);
        const Sight whole = dim == 8 ? detail::leafSight(map, origin, kVoxel, kMargin)
                                     : detail::cubeSight(map, origin, dim, kVoxel, kMargin);
        ++cubes[static_cast<std::size_t>(whole)];
        if (whole == Sight::kUnknown) continue;
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j)
            for (int k = 0; k < dim; ++k) {
              const Vec3d p = origin.offsetBy(i, j, k).asVec3d() * kVoxel;
              EXPECT_EQ(map.sight(p, kMargin), whole) << map.name() << " cube " << origin << " voxel " << p;
              if (map.sight(p, kMargin) != whole) return cubes;
            }
      }
  return cubes;
}

TEST(LeafSight, WhatALeafIsToldEveryVoxelIsToo) {
  for (const RangeMap& map : {wallWithABox(), tiltedPlaneAlongZ()}) {
    const std::array<std::size_t, 4> leaves = cubesTold(map, 8);
    // The shortcut answers for most leaves: in front, behind and beside.
    EXPECT_GT(leaves[static_cast<std::size_t>(Sight::kEmpty)], 100u);
    EXPECT_GT(leaves[static_cast<std::size_t>(Sight::kBehind)], 100u);
    EXPECT_GT(leaves[static_cast<std::size_t>(Sight::kOutside)], 100u);
  }
}

TEST(LeafSight, WhatACubeIsToldEveryVoxelIsToo) {
  // The cubes of 4 voxels a side that carving splits a leaf into when a map
  // cannot speak for the whole leaf at once (detail::BlockVotes): they decide
  // where leaves cannot.
  for (const RangeMap& map : {wallWithABox(), tiltedPlaneAlongZ()}) {
    const std::array<std::size_t, 4> cubes = cubesTold(map, 4);
    for (const Sight s : {Sight::kEmpty, Sight::kBehind, Sight::kOutside})
      EXPECT_GT(cubes[static_cast<std::size_t>(s)], 1000u) << map.name();
    std::size_t decidedInUnknownLeaves = 0;
    for (int x = -96; x <= 96; x += 8)
      for (int y = -96; y <= 96; y += 8)
        for (int z = -16; z <= 160; z += 8) {
          if (detail::leafSight(map, Coord(x, y, z), kVoxel, kMargin) != Sight::kUnknown) continue;
          for (int c = 0; c < 8; ++c) {
            const Coord cube(x + (c & 1) * 4, y + ((c >> 1) & 1) * 4, z + (c >> 2) * 4);
            decidedInUnknownLeaves += detail::cubeSight(map, cube, 4, kVoxel, kMargin) != Sight::kUnknown;
          }
        }
    EXPECT_GT(decidedInUnknownLeaves, 100u) << map.name();
  }
}

}  // namespace
}  // namespace levelfuse
