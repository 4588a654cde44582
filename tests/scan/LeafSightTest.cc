// What a range map says of a whole leaf node at once (detail::leafSight), of
// many points at once (RangeMap::sights) and carving's votes on blocks
// (detail::BlockVotes): never other than what it says of each voxel; and
// the boxes and balls a map says it cannot see (RangeMap::mayBeSeenIn,
// RangeMap::missesBall) are outside its sight at every point.

#include "../../src/scan/CarvingVotes.h"
#include "../../src/scan/LeavesReached.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/scan/PackedRangeMap.h>
#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/synth/Synth.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
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

/// A room 3 x 3 x 2.5 m with a box on its floor and a sphere, seen by a
/// spherical scanner standing in it; a sector of rays without returns. With
/// `wholeTurn` the scanner sweeps every azimuth, else 300 degrees of them.
RangeMap roomAroundAScanner(bool wholeTurn) {
  const shapes::Box room{Vec3d(0.0, 0.0, 1.25), Vec3d(1.5, 1.5, 1.25)};
  const shapes::Box box{Vec3d(0.6, 0.5, 0.3), Vec3d(0.3, 0.25, 0.3)};
  const shapes::Sphere ball{Vec3d(-0.7, 0.4, 1.2), 0.3};
  const auto distance = [&](const Vec3d& p) { return std::min(-room(p), std::min(box(p), ball(p))); };
  const synth::View view = synth::sphericalView(Vec3d(0.1, -0.05, 1.0), wholeTurn ? -180.0 : -150.0,
                                                wholeTurn ? 180.0 : 150.0, -70.0, 70.0, 2.0,
                                                wholeTurn ? "room, whole turn" : "room");
  RangeMap map = synth::renderDistanceFunction(distance, view, synth::Noise{}, 0.002);
  std::vector<float> ranges;
  for (int v = 0; v < map.height(); ++v)
    for (int u = 0; u < map.width(); ++u) ranges.push_back(v > 40 && v < 50 && u > 20 && u < 30 ? NAN : map.reading(u, v));
  return RangeMap::spherical(map.width(), map.height(), ranges, map.sphericalProjection(), map.mapToWorld(), 0.002,
                             map.name());
}

/// The same room seen on rows spaced unevenly, as a spinning LiDAR's lasers
/// are: 35 rows 2.5 degrees apart from -70 degrees, then 35 rows 1.5 apart.
RangeMap roomOnUnevenRows() {
  const shapes::Box room{Vec3d(0.0, 0.0, 1.25), Vec3d(1.5, 1.5, 1.25)};
  const shapes::Box box{Vec3d(0.6, 0.5, 0.3), Vec3d(0.3, 0.25, 0.3)};
  const shapes::Sphere ball{Vec3d(-0.7, 0.4, 1.2), 0.3};
  const auto distance = [&](const Vec3d& p) { return std::min(-room(p), std::min(box(p), ball(p))); };
  synth::View view = synth::sphericalView(Vec3d(0.1, -0.05, 1.0), -150.0, 150.0, -70.0, 70.0, 2.0, "room, uneven rows");
  view.spherical.rowElevations.clear();
  for (int r = 0; r < view.height; ++r)
    view.spherical.rowElevations.push_back((r <= 35 ? -70.0 + 2.5 * r : 17.5 + 1.5 * (r - 35)) * M_PI / 180.0);
  return synth::renderDistanceFunction(distance, view, synth::Noise{}, 0.002);
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
        const std::optional<Sight> told = dim == 8 ? detail::leafSight(map, origin, kVoxel, kMargin)
                                                   : detail::cubeSight(map, origin, dim, kVoxel, kMargin);
        if (!told) continue;
        const Sight whole = *told;
        ++cubes[static_cast<std::size_t>(whole)];
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
  for (const RangeMap& map : {wallWithABox(), tiltedPlaneAlongZ(), roomAroundAScanner(false), roomOnUnevenRows()}) {
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
  for (const RangeMap& map : {wallWithABox(), tiltedPlaneAlongZ(), roomAroundAScanner(false), roomOnUnevenRows()}) {
    const std::array<std::size_t, 4> cubes = cubesTold(map, 4);
    for (const Sight s : {Sight::kEmpty, Sight::kBehind, Sight::kOutside})
      EXPECT_GT(cubes[static_cast<std::size_t>(s)], 1000u) << map.name();
    std::size_t decidedInUnknownLeaves = 0;
    for (int x = -96; x <= 96; x += 8)
      for (int y = -96; y <= 96; y += 8)
        for (int z = -16; z <= 160; z += 8) {
          if (detail::leafSight(map, Coord(x, y, z), kVoxel, kMargin)) continue;
          for (int c = 0; c < 8; ++c) {
            const Coord cube(x + (c & 1) * 4, y + ((c >> 1) & 1) * 4, z + (c >> 2) * 4);
            decidedInUnknownLeaves += detail::cubeSight(map, cube, 4, kVoxel, kMargin).has_value();
          }
        }
    EXPECT_GT(decidedInUnknownLeaves, 100u) << map.name();
  }
}

TEST(LeafSight, AFootprintWithoutReadingsIsUnknownToEveryVoxelUnlessMissesAreEmpty) {
  // The wall's hole (pixels 60 to 69, rows 5 to 11) has no readings: a cube
  // whose footprint lies within it is unknown to each of its voxels, and
  // told so at once. Where misses are empty, a pixel without a reading may
  // say empty: then each voxel is asked (cubesTold checks every answer).
  const std::array<std::size_t, 4> holes = cubesTold(wallWithABox(), 4);
  EXPECT_GT(holes[static_cast<std::size_t>(Sight::kUnknown)], 10u);
  RangeMap misses = wallWithABox();
  misses.setMissesAreEmpty(true, 0);
  const std::array<std::size_t, 4> cubes = cubesTold(misses, 4);
  EXPECT_EQ(cubes[static_cast<std::size_t>(Sight::kUnknown)], 0u);
  EXPECT_GT(cubes[static_cast<std::size_t>(Sight::kEmpty)], 1000u);
}

TEST(LeafSight, AFootprintNearAHoleIsToldFromItsOwnPixels) {
  // The pixels themselves tell what the blocks' bounds cannot: the 8 x 8
  // block of pixels 56 to 63 and rows 0 to 7 holds part of the hole, pixels
  // 56 to 59 of rows 5 to 7 all have readings (the wall, 2 m).
  const RangeMap map = wallWithABox();
  double lo = 0.0, hi = 0.0;
  bool complete = true;
  ASSERT_TRUE(map.readingBounds(56.0, 5.0, 59.0, 7.0, lo, hi, &complete));
  EXPECT_FALSE(complete);
  const auto wall = [](float r) { return r == 2.0f; };
  const auto hole = [](float r) { return !(r == r); };
  EXPECT_TRUE(map.everyPixel(56, 5, 59, 7, wall));
  EXPECT_FALSE(map.everyPixel(56, 5, 60, 7, wall));  // one column of the hole
  EXPECT_TRUE(map.everyPixel(61, 6, 68, 10, hole));  // within the hole
  EXPECT_FALSE(map.everyPixel(59, 6, 68, 10, hole));
  EXPECT_TRUE(map.everyPixel(-5, -5, 1000, 4, wall));  // clamped to the map: rows 0 to 4 are the wall's
  EXPECT_FALSE(map.everyPixel(-5, -5, 1000, 1000, wall));
  // The cubes behind the wall that project beside the hole, within a block
  // that holds part of it, are told behind at once.
  std::size_t besideTheHole = 0, toldBehind = 0;
  for (int x = -96; x <= 96; x += 4)
    for (int y = -96; y <= 96; y += 4)
      for (int z = -16; z <= 160; z += 4) {
        const Coord origin(x, y, z);
        const Vec3d centre = map.worldToMap().transform(origin.asVec3d() * kVoxel + Vec3d(1.5 * kVoxel));
        const openvdb::math::Vec2d uv = map.project(centre);
        if (!(centre.z() > 2.1 && uv.x() > 56.6 && uv.x() < 57.4 && uv.y() > 4.0 && uv.y() < 6.5)) continue;
        ++besideTheHole;
        toldBehind += detail::cubeSight(map, origin, 4, kVoxel, kMargin) == Sight::kBehind;
      }
  EXPECT_GT(besideTheHole, 3u);
  EXPECT_EQ(toldBehind, besideTheHole);
}

TEST(LeafSight, AWholeTurnSpeaksForLeavesAllRound) {
  const std::array<std::size_t, 4> leaves = cubesTold(roomAroundAScanner(true), 8);
  EXPECT_GT(leaves[static_cast<std::size_t>(Sight::kEmpty)], 100u);
  EXPECT_GT(leaves[static_cast<std::size_t>(Sight::kBehind)], 100u);
}

TEST(LeavesReached, EveryVoxelAReadingReachesIsInALeafReached) {
  // The leaves and cubes that accumulation visits (DataTermGrids::integrate)
  // hold every voxel within the reach of a reading: checked voxel by voxel.
  const double reach = 0.07;
  for (const RangeMap& map : {wallWithABox(), roomAroundAScanner(false), roomAroundAScanner(true), roomOnUnevenRows()}) {
    const std::vector<Coord> leaves = detail::leavesReached(map, kVoxel, reach);
    const detail::CellSpans cells(map);
    const detail::UsableSpans spans(cells);
    std::size_t reached = 0;
    for (int x = -96; x < 96; ++x)
      for (int y = -96; y < 96; ++y)
        for (int z = -16; z < 160; ++z) {
          const Coord ijk(x, y, z);
          RangeMap::LocalSample s;
          const Vec3d p = map.worldToMap().transform(ijk.asVec3d() * kVoxel);
          if (!map.sampleLocal(p, reach, s)) continue;
          ++reached;
          if (map.canProject(p)) {
            const openvdb::math::Vec2d uv = map.project(p);
            ASSERT_TRUE(cells.mayReach(uv.x(), uv.y(), map.readingCoordinate(p), reach)) << map.name() << " voxel " << ijk;
          }
          const Coord leaf(x & ~7, y & ~7, z & ~7);
          ASSERT_TRUE(std::binary_search(leaves.begin(), leaves.end(), leaf)) << map.name() << " voxel " << ijk;
          ASSERT_TRUE(detail::leafMayBeReached(spans, leaf, kVoxel, reach)) << map.name() << " voxel " << ijk;
          const int cube = (((x >> 2) & 1) << 2) | (((y >> 2) & 1) << 1) | ((z >> 2) & 1);
          ASSERT_TRUE(detail::leafCubesMayBeReached(spans, leaf, kVoxel, reach) & (1 << cube))
              << map.name() << " voxel " << ijk;
        }
    EXPECT_GT(reached, 10000u) << map.name();
  }
}

TEST(LeavesReached, TheDenseAndTheSparseMarksFindTheSameLeaves) {
  // The leaves of a frame marked in a dense block of bits (the default for a
  // room) and in sparse trees (for bounds too large for a block), for every
  // kind of map; both sorted, each leaf once.
  for (const RangeMap& map : {wallWithABox(), roomAroundAScanner(false), roomAroundAScanner(true), roomOnUnevenRows()})
    for (const double reach : {0.0, 0.07, 0.5}) {
      const std::vector<Coord> dense = detail::leavesReached(map, kVoxel, reach);
      const std::vector<Coord> sparse = detail::leavesReached(map, kVoxel, reach, 0.0);
      EXPECT_GT(dense.size(), 10u) << map.name();
      EXPECT_TRUE(std::adjacent_find(dense.begin(), dense.end(), [](const Coord& a, const Coord& b) {
                    return !(a < b);
                  }) == dense.end())
          << map.name() << ": not sorted, or a leaf twice";
      EXPECT_EQ(dense, sparse) << map.name() << " reach " << reach;
    }
}

TEST(LeavesReached, TheEmptyStretchOfADepthDiscontinuityIsNotReached) {
  // The box stands 0.5 m in front of the wall over pixels 30 to 49 and rows
  // 20 to 39; the cells across its edge are not usable, so no reading is
  // interpolated between 1.5 and 2 m.
  const RangeMap map = wallWithABox();
  const detail::UsableSpans spans(map);
  const auto meets = [&spans](double u0, double u1, double lo, double hi) {
    return spans.meet(u0, 25.0, u1, 30.0, lo, hi);
  };
  EXPECT_TRUE(meets(44.0, 56.0, 1.45, 1.55));   // the box
  EXPECT_TRUE(meets(44.0, 56.0, 1.95, 2.05));   // the wall
  EXPECT_FALSE(meets(44.0, 56.0, 1.6, 1.9));    // between them
  EXPECT_TRUE(meets(44.0, 56.0, 1.45, 2.05));   // both
  EXPECT_FALSE(meets(33.0, 40.0, 1.95, 2.05));  // the wall, behind the box
  EXPECT_FALSE(meets(-20.0, -5.0, 1.95, 2.05)); // beside the map
  // A window reaching far beyond the map (a footprint near the camera's plane)
  // is clamped to it.
  EXPECT_TRUE(meets(44.0, 1e15, 1.95, 2.05));
  EXPECT_TRUE(meets(-1e15, 1e15, 1.45, 1.55));
  // The reading bounds of the blocks see one span from the box to the wall.
  double lo = 0.0, hi = 0.0;
  ASSERT_TRUE(map.readingBounds(44.0, 25.0, 57.0, 31.0, lo, hi));
  EXPECT_EQ(lo, 1.5);
  EXPECT_EQ(hi, 2.0);
  ASSERT_TRUE(map.readingBounds(-1e15, 25.0, 1e15, 31.0, lo, hi));
  EXPECT_EQ(lo, 1.5);
  EXPECT_EQ(hi, 2.0);
  // Cubes of 4 voxels between the box and the wall, over its edge, are not
  // reached: the culling of accumulation asks of the usable cells.
  std::size_t between = 0, culled = 0;
  for (int x = -96; x <= 96; x += 4)
    for (int y = -96; y <= 96; y += 4)
      for (int z = -16; z <= 160; z += 4) {
        const Vec3d centre = map.worldToMap().transform(Coord(x, y, z).asVec3d() * kVoxel + Vec3d(1.5 * kVoxel));
        const openvdb::math::Vec2d uv = map.project(centre);
        if (!(centre.z() > 1.62 && centre.z() < 1.88 && uv.y() > 22.0 && uv.y() < 37.0 && std::fabs(uv.x() - 49.5) < 3.0))
          continue;
        ++between;
        culled += !detail::cubeMayBeReached(spans, Coord(x, y, z), 4, kVoxel, 0.05);
      }
  EXPECT_GT(between, 5u);
  EXPECT_EQ(culled, between);
}

/// Points over a box around the readings of the maps above (and behind the
/// camera), from a fixed sequence of pseudo-random numbers.
std::vector<Vec3d> pointsAround(std::size_t count) {
  std::vector<Vec3d> points(count);
  std::uint64_t state = 12345;
  const auto uniform = [&state](double lo, double hi) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  for (Vec3d& p : points) p = Vec3d(uniform(-2.0, 2.0), uniform(-2.0, 2.0), uniform(-0.5, 3.3));
  return points;
}

TEST(Sights, ManyPointsAtOnceAreToldWhatEachIsAlone) {
  RangeMap missesEmpty = wallWithABox();
  missesEmpty.setMissesAreEmpty(true, 0);
  // 1000 points: the batches of 64 and a last short one.
  const std::vector<Vec3d> points = pointsAround(1000);
  for (const RangeMap& map :
       {wallWithABox(), missesEmpty, tiltedPlaneAlongZ(), roomAroundAScanner(false), roomOnUnevenRows()}) {
    std::vector<Sight> together(points.size());
    map.sights(points.data(), points.size(), kMargin, together.data());
    std::array<std::size_t, 4> told{};
    for (std::size_t i = 0; i < points.size(); ++i) {
      ASSERT_EQ(together[i], map.sight(points[i], kMargin)) << map.name() << " point " << points[i];
      ++told[static_cast<std::size_t>(together[i])];
    }
    for (const Sight s : {Sight::kOutside, Sight::kEmpty, Sight::kBehind})
      EXPECT_GT(told[static_cast<std::size_t>(s)], 20u) << map.name();
  }
}

TEST(BlockVotes, TheVotesOnBlocksAreTheVotesOnEachVoxel) {
  // Blocks around the wall and the box, each asking of some of its voxels
  // (every voxel, one, or a pseudo-random half), voted on by a camera, the
  // same camera whose misses are empty, and parallel rays; PointVotes asks the
  // same voxels one by one.
  using Mask = detail::BlockVotes::Mask;
  std::vector<Coord> origins;
  std::vector<Mask> asked;
  std::vector<Vec3d> voxels;  // the asked voxels' centres, block by block, in offset order
  std::uint64_t state = 777;
  for (int x = -48; x <= 48; x += 8)
    for (int y = -48; y <= 48; y += 8)
      for (int z = 64; z <= 120; z += 8) {
        Mask mask;
        const std::size_t kind = origins.size() % 3;
        for (openvdb::Index o = 0; o < Mask::SIZE; ++o) {
          state = state * 6364136223846793005ULL + 1442695040888963407ULL;
          if (kind == 0 || (kind == 1 && o == 300) || (kind == 2 && (state >> 63))) mask.setOn(o);
        }
        origins.emplace_back(x, y, z);
        asked.push_back(mask);
        for (auto it = mask.beginOn(); it; ++it)
          voxels.push_back((origins.back() + openvdb::FloatTree::LeafNodeType::offsetToLocalCoord(it.pos())).asVec3d() *
                           kVoxel);
      }
  detail::BlockVotes blocks(origins, asked, kVoxel);
  detail::PointVotes points(voxels.size(), [&voxels](std::size_t i) { return voxels[i]; });
  RangeMap closer = wallWithABox();
  closer.setMissesAreEmpty(true, 0);
  std::size_t index = 0;
  for (const RangeMap& map : {wallWithABox(), closer, tiltedPlaneAlongZ()}) {
    blocks.add(map, kMargin, index);
    points.add(map, kMargin, index++);
  }
  std::size_t next = 0, inside = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b)
    blocks.forEachAsked(b, [&](openvdb::Index o, bool in) {
      ASSERT_LT(next, voxels.size());
      EXPECT_EQ(in, points.inside(next)) << "block " << blocks.origin(b) << " voxel " << o;
      inside += in;
      ++next;
    });
  EXPECT_EQ(next, voxels.size());
  // Both answers occur: the test can tell them apart.
  EXPECT_GT(inside, 1000u);
  EXPECT_GT(voxels.size() - inside, 1000u);
}

/// Each voxel's votes, blocks and voxels in order: its balance and whether it was seen empty.
std::vector<std::pair<std::int32_t, bool>> votesOfEachVoxel(const detail::BlockVotes::Kept& kept) {
  std::vector<std::pair<std::int32_t, bool>> votes;
  for (const auto& [origin, block] : kept)
    for (auto it = block.asked.beginOn(); it; ++it) {
      const std::int32_t own = block.voxels.empty() ? 0 : block.voxels[block.rank(it.pos())];
      votes.emplace_back(block.uniform + own, block.empty || block.voxelEmpty.isOn(it.pos()));
    }
  return votes;
}

TEST(BlockVotes, VotesKeptFromFewerMapsTakeTheRestAlone) {
  // Blocks and points voted on by the first two of four maps, kept, then
  // asked again with more blocks and points (and fewer voxels of the kept
  // blocks) from the first map one of them has not counted: the votes of
  // all four maps cast once each, as from scratch.
  using Mask = detail::BlockVotes::Mask;
  RangeMap closer = wallWithABox();
  closer.setMissesAreEmpty(true, 0);
  const std::vector<RangeMap> maps{tiltedPlaneAlongZ(), wallWithABox(), closer, tiltedPlaneAlongZ()};
  std::vector<Coord> origins;
  std::vector<Mask> asked, everyVoxel;
  std::uint64_t state = 99;
  for (int x = -48; x <= 48; x += 8)
    for (int y = -48; y <= 48; y += 16)
      for (int z = 64; z <= 120; z += 8) {
        Mask mask;
        for (openvdb::Index o = 0; o < Mask::SIZE; ++o) {
          state = state * 6364136223846793005ULL + 1442695040888963407ULL;
          if (state >> 62) mask.setOn(o);  // three in four
        }
        origins.emplace_back(x, y, z);
        asked.push_back(mask);
        everyVoxel.emplace_back(true);
      }
  const std::size_t half = origins.size() / 2;
  const auto centre = [&origins](std::size_t i) { return (origins[i].asVec3d() + Vec3d(3.5)) * kVoxel; };

  detail::BlockVotes scratch(origins, asked, kVoxel);
  detail::PointVotes scratchPoints(origins.size(), centre);
  for (std::size_t i = 0; i < maps.size(); ++i) {
    scratch.add(maps[i], kMargin, i);
    scratchPoints.add(maps[i], kMargin, i);
  }

  detail::BlockVotes::Kept kept;
  {
    detail::BlockVotes early(std::vector<Coord>(origins.begin(), origins.begin() + half),
                             std::vector<Mask>(everyVoxel.begin(), everyVoxel.begin() + half), kVoxel);
    for (std::size_t i = 0; i < 2; ++i) early.add(maps[i], kMargin, i);
    early.keepIn(kept);
  }
  detail::PointVotes earlyPoints(half, centre);
  for (std::size_t i = 0; i < 2; ++i) earlyPoints.add(maps[i], kMargin, i);

  detail::BlockVotes later(origins, asked, kVoxel, &kept);
  EXPECT_TRUE(kept.empty());  // every kept block taken
  detail::PointVotes laterPoints(origins.size(), centre);
  for (std::size_t i = 0; i < half; ++i) laterPoints.restore(i, earlyPoints.record(i));
  EXPECT_EQ(later.firstMapNeeded(), 0u);  // the new blocks need every map
  for (std::size_t i = std::min(later.firstMapNeeded(), laterPoints.firstMapNeeded()); i < maps.size(); ++i) {
    later.add(maps[i], kMargin, i);
    laterPoints.add(maps[i], kMargin, i);
  }
  const auto everyMapCounted = [&maps](std::size_t first) { return first == maps.size() || first == detail::kNoMapNeeded; };
  EXPECT_TRUE(everyMapCounted(later.firstMapNeeded()));
  for (std::size_t i = 0; i < origins.size(); ++i) {
    EXPECT_EQ(laterPoints.record(i).balance, scratchPoints.record(i).balance) << "point " << i;
    EXPECT_EQ(laterPoints.record(i).empty, scratchPoints.record(i).empty) << "point " << i;
  }
  detail::BlockVotes::Kept fromScratch, fromKept;
  scratch.keepIn(fromScratch);
  later.keepIn(fromKept);
  const auto expected = votesOfEachVoxel(fromScratch), got = votesOfEachVoxel(fromKept);
  ASSERT_EQ(got.size(), expected.size());
  std::size_t differ = 0, empty = 0, behind = 0;
  for (std::size_t v = 0; v < got.size(); ++v) {
    differ += got[v] != expected[v];
    empty += expected[v].second;
    behind += !expected[v].second && expected[v].first > 0;
  }
  EXPECT_EQ(differ, 0u);
  // The maps say all three things of these voxels: the test can tell them apart.
  EXPECT_GT(empty, 1000u);
  EXPECT_GT(behind, 1000u);
  EXPECT_GT(got.size() - empty - behind, 1000u);
  // Kept once every map is counted, they need none.
  const detail::BlockVotes again(origins, asked, kVoxel, &fromKept);
  EXPECT_TRUE(everyMapCounted(again.firstMapNeeded()));
}

/// Calls visit(corner) for the 20 x 20 x 20 cells of 0.4 m over 8 m around
/// the origin (`corner` the least), until it returns false.
template <typename Visit>
void forEachCellAroundTheOrigin(const Visit& visit) {
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      for (int k = 0; k < 20; ++k)
        if (!visit(Vec3d(i, j, k) * 0.4 - Vec3d(4.0))) return;
}

/// Boxes 0.4 m a side over 8 m around the origin: where `map` says it may
/// not see a box, every point of it (a 7 x 7 x 7 lattice, corners included)
/// is outside its sight; its packed shell answers alike. Returns how many
/// boxes it may not see, and how many it may.
std::pair<int, int> boxesTold(const RangeMap& map) {
  const PackedRangeMap packed{RangeMap(map)};
  std::pair<int, int> told{0, 0};
  forEachCellAroundTheOrigin([&](const Vec3d& corner) {
    const openvdb::BBoxd box(corner, corner + Vec3d(0.4));
    const bool may = map.mayBeSeenIn(box);
    EXPECT_EQ(packed.shell().mayBeSeenIn(box), may) << map.name() << " box at " << box.min();
    ++(may ? told.second : told.first);
    if (may) return true;
    for (int a = 0; a <= 6; ++a)
      for (int b = 0; b <= 6; ++b)
        for (int c = 0; c <= 6; ++c) {
          const Vec3d p = box.min() + box.extents() * Vec3d(a, b, c) / 6.0;
          if (map.sight(p, kMargin) != Sight::kOutside) {
            ADD_FAILURE() << map.name() << " says it cannot see the box at " << box.min() << ", but sees " << p;
            return false;
          }
        }
    return true;
  });
  return told;
}

/// What `told` (boxesTold or ballsTold: how many of the cells a map says it
/// cannot see, and how many it may) finds of each kind of map: a camera and
/// parallel rays cannot see many, a spherical scanner is not asked.
template <typename Told>
void expectEachKindTold(const Told& told) {
  const auto [cameraCannot, cameraMay] = told(wallWithABox());
  EXPECT_GT(cameraCannot, 1000) << "behind the camera and beside its pixels";
  EXPECT_GT(cameraMay, 300) << "its view";
  const auto [raysCannot, raysMay] = told(tiltedPlaneAlongZ());
  EXPECT_GT(raysCannot, 1000) << "beside the patch of parallel rays";
  EXPECT_GT(raysMay, 300) << "along the rays, both ways";
  const auto [scannerCannot, scannerMay] = told(roomAroundAScanner(false));
  EXPECT_EQ(scannerCannot, 0) << "a spherical scanner may see any cell";
  EXPECT_EQ(scannerMay, 20 * 20 * 20);
}

TEST(MayBeSeenIn, ABoxAMapCannotSeeIsOutsideItsSightEverywhere) { expectEachKindTold(boxesTold); }

/// Balls of radius 0.3 m centred 0.4 m apart over 8 m around the origin:
/// where `map` says it misses a ball, every point of it (a lattice of 9 a
/// side over its box, the points within the ball, and the six points where
/// its axes meet its surface) is outside its sight. Returns how many balls
/// it misses, and how many it may not.
std::pair<int, int> ballsTold(const RangeMap& map) {
  constexpr double kRadius = 0.3;
  std::pair<int, int> told{0, 0};
  forEachCellAroundTheOrigin([&](const Vec3d& corner) {
    const Vec3d centre = corner + Vec3d(0.2);
    const bool misses = map.missesBall(centre, kRadius);
    ++(misses ? told.first : told.second);
    if (!misses) return true;
    std::vector<Vec3d> points;
    for (int axis = 0; axis < 3; ++axis)
      for (const double side : {-kRadius, kRadius}) {
        Vec3d p = centre;
        p[axis] += side;
        points.push_back(p);
      }
    for (int a = 0; a <= 8; ++a)
      for (int b = 0; b <= 8; ++b)
        for (int c = 0; c <= 8; ++c) {
          const Vec3d offset = (Vec3d(a, b, c) / 4.0 - Vec3d(1.0)) * kRadius;
          if (offset.length() <= kRadius) points.push_back(centre + offset);
        }
    for (const Vec3d& p : points)
      if (map.sight(p, kMargin) != Sight::kOutside) {
        ADD_FAILURE() << map.name() << " says it misses the ball at " << centre << ", but sees " << p;
        return false;
      }
    return true;
  });
  return told;
}

TEST(MissesBall, ABallAMapMissesIsOutsideItsSightEverywhere) { expectEachKindTold(ballsTold); }

TEST(MissesBall, ABallJustInsideAnEdgeOfTheImageIsNotMissed) {
  // A point on the ray of pixel (0, 29.5) of the camera, on the plane through
  // its centre and the image's left edge (u = 0: fx x + cx z = 0 in its
  // frame), and a ball whose surface reaches a hair's breadth inside that
  // plane: seen; moved a little farther out: missed.
  const RangeMap map = wallWithABox();
  const Vec3d onTheEdge = map.pointAt(0.0, 29.5, 1.0);
  const Vec3d outward = map.mapToWorld().transform3x3(Vec3d(-60.0, 0.0, -39.5)).unit();
  const double radius = 0.05;
  EXPECT_FALSE(map.missesBall(onTheEdge + outward * (radius - 1e-4), radius));
  EXPECT_TRUE(map.missesBall(onTheEdge + outward * (radius + 1e-3), radius));
  // Behind the camera.
  const Vec3d camera = map.mapToWorld().getTranslation();
  const Vec3d axis = map.mapToWorld().transform3x3(Vec3d(0.0, 0.0, 1.0));
  EXPECT_TRUE(map.missesBall(camera - axis * 0.2, 0.1));
  EXPECT_FALSE(map.missesBall(camera - axis * 0.05, 0.1));
}

}  // namespace
}  // namespace levelfuse
