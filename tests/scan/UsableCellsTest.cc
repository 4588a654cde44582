// Which 2x2 cells of readings a range map interpolates (its usable cells): a
// smooth surface seen at grazing incidence, whose neighbouring readings lie
// many ray spacings apart, is interpolated; a depth step is not, even among
// steep readings. Where a cell is usable, space carving asks the reading the
// data term interpolates.

#include "support/ScannerPoses.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/synth/Scenes.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;
using Mat4d = openvdb::math::Mat4d;
using Sight = RangeMap::Sight;
using test::kDegree;

/// A grid of rays with its size.
struct RayGrid {
  SphericalProjection projection;
  int columns = 0, rows = 0;
};

/// The ranges along the grid's rays (scanner frame) that `rangeOf` gives.
std::vector<float> rangesAlong(const RayGrid& g, const std::function<double(const Vec3d&)>& rangeOf) {
  std::vector<float> ranges;
  for (int v = 0; v < g.rows; ++v)
    for (int u = 0; u < g.columns; ++u)
      ranges.push_back(static_cast<float>(rangeOf(sphericalDirection(g.projection, u, v))));
  return ranges;
}

// ---- a floor 0.5 m below a tripod ----

constexpr double kTripodHeight = 0.5;

/// Azimuths 5 degrees either side of +x, and the elevations that meet the
/// floor at incidences from `nearest` to `farthest` degrees, 0.1 degrees apart.
RayGrid floorGrid(double nearest, double farthest) {
  const double step = 0.1;
  RayGrid g;
  g.columns = 101;
  g.rows = static_cast<int>(std::lround((farthest - nearest) / step)) + 1;
  g.projection = SphericalProjection(-5.0 * kDegree, step * kDegree, (nearest - 90.0) * kDegree, step * kDegree);
  return g;
}

double floorRange(const Vec3d& ray) { return -kTripodHeight / ray.z(); }
/// The angle (degrees) between a ray and the floor's normal where they meet.
double floorIncidence(const Vec3d& ray) { return std::acos(-ray.z()) / kDegree; }

RangeMap floorMap(const RayGrid& g, std::vector<float> ranges, double sigma) {
  return RangeMap::spherical(g.columns, g.rows, std::move(ranges), g.projection, Mat4d::identity(), sigma, "floor");
}

/// The incidence of cell (i, j): that of the ray through its middle.
double cellIncidence(const RayGrid& g, int i, int j) {
  return floorIncidence(sphericalDirection(g.projection, i + 0.5, j + 0.5));
}

TEST(UsableCells, AFloorIsInterpolatedUpToEightyFiveDegrees) {
  // At 80 degrees neighbouring rows' readings lie 5.7 ray spacings apart,
  // more than the four a cell may span on a surface seen square on.
  const RayGrid g = floorGrid(60.0, 88.0);
  std::mt19937_64 random(3);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  for (const double noise : {0.0, 0.002}) {
    std::vector<float> ranges = rangesAlong(g, floorRange);
    for (float& r : ranges) r = static_cast<float>(r + noise * gaussian(random));
    const RangeMap map = floorMap(g, std::move(ranges), std::max(noise, 0.0005));
    int before = 0, beforeUsable = 0, pastTheCap = 0, pastTheCapUsable = 0;
    double firstUnusable = 90.0;
    for (int j = 0; j + 1 < g.rows; ++j)
      for (int i = 0; i + 1 < g.columns; ++i) {
        const double incidence = cellIncidence(g, i, j);
        if (incidence < 85.0) {
          ++before;
          beforeUsable += map.cellUsable(i, j);
          if (!map.cellUsable(i, j)) firstUnusable = std::min(firstUnusable, incidence);
        } else if (incidence > 87.0) {
          ++pastTheCap;
          pastTheCapUsable += map.cellUsable(i, j);
        }
      }
    EXPECT_EQ(beforeUsable, before) << "noise " << noise << ": the first unusable cell at " << firstUnusable
                                    << " degrees";
    // Past about 86 degrees a cell spans more than 12 ray spacings: a step.
    EXPECT_GE(pastTheCap, 1000);
    EXPECT_EQ(pastTheCapUsable, 0) << "noise " << noise;
  }
}

TEST(UsableCells, ADropInAFloorSeenAtGrazingIncidenceIsAStep) {
  // Beyond row 120 (80 degrees) the floor lies 4.3 cm farther: the cells
  // across that row span 14 ray spacings, no more than three times their
  // neighbours' steps, but beyond the 12 a steep surface may span.
  const RayGrid g = floorGrid(68.0, 86.0);
  const int dropRow = 120;
  std::vector<float> ranges = rangesAlong(g, floorRange);
  for (int v = dropRow + 1; v < g.rows; ++v)
    for (int u = 0; u < g.columns; ++u) ranges[static_cast<std::size_t>(v * g.columns + u)] += 0.043f;
  const RangeMap map = floorMap(g, std::move(ranges), 0.0005);
  ASSERT_NEAR(cellIncidence(g, 50, dropRow), 80.0, 0.1);
  int across = 0, before = 0, beyond = 0;
  for (int i = 0; i + 1 < g.columns; ++i) {
    across += map.cellUsable(i, dropRow);
    before += map.cellUsable(i, dropRow - 1);
    beyond += map.cellUsable(i, dropRow + 1);
  }
  EXPECT_EQ(across, 0);
  EXPECT_EQ(before, g.columns - 1);
  EXPECT_EQ(beyond, g.columns - 1);
}

// ---- a wall 4 m before a scanner, a box before the wall ----

/// Azimuths and elevations 20 degrees either side of +x, half a degree apart:
/// 3.5 cm between rays at the wall.
RayGrid wallGrid() {
  RayGrid g;
  g.columns = g.rows = 81;
  g.projection = SphericalProjection(-20.0 * kDegree, 0.5 * kDegree, -20.0 * kDegree, 0.5 * kDegree);
  return g;
}

/// The wall x = 4 and, 1 m before it, the face x = 3 of a box, |y| < 0.4 and |z| < 0.3.
double wallBehindABox(const Vec3d& ray) {
  const double atBox = 3.0 / ray.x();
  const Vec3d p = ray * atBox;
  return std::fabs(p.y()) < 0.4 && std::fabs(p.z()) < 0.3 ? atBox : 4.0 / ray.x();
}

bool onTheBox(const RayGrid& g, int u, int v) {
  const Vec3d ray = sphericalDirection(g.projection, u, v);
  return wallBehindABox(ray) < 3.5 / ray.x();
}

TEST(UsableCells, ABoxBeforeAWallIsNotInterpolatedAcrossItsEdges) {
  const RayGrid g = wallGrid();
  const RangeMap map = RangeMap::spherical(g.columns, g.rows, rangesAlong(g, wallBehindABox), g.projection,
                                           Mat4d::identity(), 0.002, "box");
  int across = 0;
  for (int j = 0; j + 1 < g.rows; ++j)
    for (int i = 0; i + 1 < g.columns; ++i) {
      const int boxPixels =
          onTheBox(g, i, j) + onTheBox(g, i + 1, j) + onTheBox(g, i, j + 1) + onTheBox(g, i + 1, j + 1);
      const bool straddles = boxPixels > 0 && boxPixels < 4;
      across += straddles;
      EXPECT_EQ(map.cellUsable(i, j), !straddles) << i << ", " << j;
    }
  EXPECT_GT(across, 50);
}

TEST(UsableCells, AStepOfAFewRaySpacingsInAWallSeenSquareOnIsAStep) {
  // Columns 41 on lie 25 cm farther: 7 ray spacings, below the 12 a steep
  // surface may span, but the neighbouring cells' readings hardly change.
  const RayGrid g = wallGrid();
  const RangeMap map = RangeMap::spherical(
      g.columns, g.rows, rangesAlong(g, [](const Vec3d& ray) { return (ray.y() < 1e-9 ? 4.0 : 4.25) / ray.x(); }),
      g.projection, Mat4d::identity(), 0.002, "stepped wall");
  int across = 0, before = 0, beyond = 0;
  for (int j = 0; j + 1 < g.rows; ++j) {
    across += map.cellUsable(40, j);
    before += map.cellUsable(39, j);
    beyond += map.cellUsable(41, j);
  }
  EXPECT_EQ(across, 0);
  EXPECT_EQ(before, g.rows - 1);
  EXPECT_EQ(beyond, g.rows - 1);
}

TEST(UsableCells, TheRoomsCellsAcrossItsEdgesAreNotInterpolated) {
  // The room scanned from three tripods, without noise: the middle of every
  // usable cell, interpolated, lies within one and a half ray spacings of the
  // room, not in the free space between a pillar's side, seen at grazing
  // incidence, and the wall behind it.
  const shapes::Room room;
  synth::SceneOptions options;
  options.resolution = 100;  // 0.9 degrees between rays
  const synth::Scene scene = synth::roomScene(room, options);
  ASSERT_EQ(scene.maps.size(), 3u);
  for (const RangeMap& map : scene.maps) {
    std::size_t usable = 0, offTheRoom = 0;
    const double step = 0.9 * kDegree;
    for (int j = 0; j + 1 < map.height(); ++j)
      for (int i = 0; i + 1 < map.width(); ++i) {
        if (!map.cellUsable(i, j)) continue;
        ++usable;
        const double r = 0.25 * (double(map.reading(i, j)) + map.reading(i + 1, j) + map.reading(i, j + 1) +
                                 map.reading(i + 1, j + 1));
        offTheRoom += std::fabs(room(map.pointAt(i + 0.5, j + 0.5, r))) > 1.5 * r * step;
      }
    EXPECT_GT(usable, 0.9 * map.validCount()) << map.name();
    EXPECT_EQ(offTheRoom, 0u) << map.name() << ": " << usable << " usable cells";
  }
}

// ---- what carving asks ----

TEST(UsableCells, TheSightOfAPointInAUsableCellIsThatOfTheReadingTheDataTermInterpolates) {
  // On the floor at 80 degrees a cell's readings span 3 cm: a point 1 cm
  // before the interpolated reading lies behind some of them and before
  // others, yet it is in front of the surface the data term sees.
  const RayGrid g = floorGrid(70.0, 86.0);
  const RangeMap map = floorMap(g, rangesAlong(g, floorRange), 0.0005);
  const double margin = 0.006;
  int asked = 0;
  for (const double u : {20.3, 50.5, 71.8})
    for (const double v : {99.25, 100.5, 101.75}) {
      const Vec3d ray = sphericalDirection(g.projection, u, v);
      ASSERT_NEAR(floorIncidence(ray), 80.0, 0.3);
      ASSERT_TRUE(map.cellUsable(static_cast<int>(u), static_cast<int>(v)));
      RangeSample s;
      ASSERT_TRUE(map.sample(ray * floorRange(ray), s));
      const double reading = floorRange(ray) - s.D;  // the interpolated reading along the ray
      EXPECT_EQ(map.sight(ray * (reading - 0.01), margin), Sight::kEmpty) << u << ", " << v;
      EXPECT_EQ(map.sight(ray * (reading + 0.01), margin), Sight::kBehind) << u << ", " << v;
      EXPECT_EQ(map.sight(ray * (reading - 0.5 * margin), margin), Sight::kUnknown) << u << ", " << v;
      EXPECT_EQ(map.sight(ray * (reading + 0.5 * margin), margin), Sight::kUnknown) << u << ", " << v;
      ++asked;
    }
  EXPECT_EQ(asked, 9);
}

TEST(UsableCells, AcrossAStepTheFourReadingsMustAgree) {
  // A point between the box and the wall, on a ray through a cell across the
  // box's edge: behind the box's readings, before the wall's.
  const RayGrid g = wallGrid();
  const RangeMap map = RangeMap::spherical(g.columns, g.rows, rangesAlong(g, wallBehindABox), g.projection,
                                           Mat4d::identity(), 0.002, "box");
  const int i = 40;
  int j = 0;
  while (j + 1 < g.rows && !(onTheBox(g, i, j) && !onTheBox(g, i, j + 1))) ++j;  // the box's top edge
  ASSERT_LT(j + 1, g.rows);
  ASSERT_FALSE(map.cellUsable(i, j));
  const Vec3d ray = sphericalDirection(g.projection, i + 0.5, j + 0.5);
  EXPECT_EQ(map.sight(ray * 3.5 / ray.x(), 0.006), Sight::kUnknown);
  EXPECT_EQ(map.sight(ray * 2.5 / ray.x(), 0.006), Sight::kEmpty);
  EXPECT_EQ(map.sight(ray * 4.5 / ray.x(), 0.006), Sight::kBehind);
}

/// A camera's 8 x 3 frame of a wall 1 m away whose columns 4 on lie `step`
/// farther, its readings' sigma 1 cm (a cell may span 6 cm of noise).
RangeMap steppedWallFrame(float step) {
  std::vector<float> depths;
  for (int v = 0; v < 3; ++v)
    for (int u = 0; u < 8; ++u) depths.push_back(u < 4 ? 1.0f : 1.0f + step);
  return RangeMap::pinhole(8, 3, std::move(depths), PinholeProjection{100.0, 100.0, 3.5, 1.0}, Mat4d::identity(), 0.01,
                           "stepped wall");
}

TEST(UsableCells, AStepBeyondTheNoiseAndFourRaySpacingsIsAStepWhereverTheNoiseAloneIsLarge) {
  // The bound is 6 sigmas (6 cm) plus 4 ray spacings at the farther reading
  // (1 cm a pixel at 1 m): 10.4 cm for a step of 10 cm, 10.44 cm for 11 cm.
  for (const float step : {0.03f, 0.06f, 0.10f}) {
    const RangeMap map = steppedWallFrame(step);
    EXPECT_TRUE(map.cellUsable(3, 0)) << step;
    EXPECT_TRUE(map.cellUsable(3, 1)) << step;
  }
  const RangeMap stepped = steppedWallFrame(0.11f);
  EXPECT_FALSE(stepped.cellUsable(3, 0));
  EXPECT_FALSE(stepped.cellUsable(3, 1));
  // Beside the step the wall is flat.
  EXPECT_TRUE(stepped.cellUsable(2, 0));
  EXPECT_TRUE(stepped.cellUsable(4, 1));
}

}  // namespace
}  // namespace levelfuse
