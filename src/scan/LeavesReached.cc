// levelfuse: the leaf nodes a range map's windows reach.

#include "LeavesReached.h"

#include <levelfuse/core/Parallel.h>
#include <levelfuse/levelset/LeafNodeWidth.h>

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <limits>

namespace levelfuse::detail {

namespace {
using openvdb::Coord;
using openvdb::Vec3d;

/// The pixels along each side of a tile whose frustum box marks the leaves
/// it may reach: larger tiles, fewer boxes to work out for a few more
/// candidate leaves (8 measured fastest on depth frames, docs/BENCHMARKS.md).
constexpr int kTile = 8;

/// The rows of tiles of a map.
int tileRows(const RangeMap& m) { return (m.height() - 2) / kTile + 1; }

/// forEachTileBox over the tiles of rows `first` to `last` - 1 of tiles.
template <typename Visit>
void forEachTileBoxOfRows(const RangeMap& m, double reach, int first, int last, const Visit& visit) {
  for (int v0 = first * kTile; v0 < last * kTile && v0 + 1 < m.height(); v0 += kTile)
    for (int u0 = 0; u0 + 1 < m.width(); u0 += kTile) {
      const int u1 = std::min(u0 + kTile, m.width() - 1), v1 = std::min(v0 + kTile, m.height() - 1);
      float nearest = std::numeric_limits<float>::max(), farthest = -nearest;
      for (int v = v0; v <= v1; ++v)
        for (int u = u0; u <= u1; ++u)
          if (m.valid(u, v)) {
            nearest = std::min(nearest, m.reading(u, v));
            farthest = std::max(farthest, m.reading(u, v));
          }
      if (nearest > farthest) continue;
      // A station's edges reach a little beyond their pixels' readings (RangeMap::edgeReadings).
      nearest -= static_cast<float>(m.edgeExtensionReach(nearest));
      farthest += static_cast<float>(m.edgeExtensionReach(farthest));
      // A tile at a station's border also stands for the border beyond it,
      // its cells' readings extrapolated there (RangeMap::borderReach).
      const double border = m.borderReach();
      const double bu0 = u0 == 0 ? -border : u0, bv0 = v0 == 0 ? -border : v0;
      const double bu1 = u1 == m.width() - 1 ? u1 + border : u1, bv1 = v1 == m.height() - 1 ? v1 + border : v1;
      if (border > 0.0 && (bu0 != u0 || bv0 != v0 || bu1 != u1 || bv1 != v1))
        for (int v = v0; v < v1; ++v)
          for (int u = u0; u < u1; ++u) {
            float lo, hi;
            if (!m.usableCellSpan(u, v, lo, hi)) continue;
            nearest = std::min(nearest, lo);
            farthest = std::max(farthest, hi);
          }
      const MapProjection& projection = m.projection();
      const double front = projection.nearestReading(nearest - reach, farthest);
      openvdb::BBoxd box;
      for (int c = 0; c < 8; ++c)
        box.expand(m.pointAt(c & 1 ? bu1 : bu0, c & 2 ? bv1 : bv0, c & 4 ? farthest + reach : front));
      if (!projection.keepsLinesStraight())
        box.expand(projection.sphericalRays().tileBulge(bu1 - bu0, bv0, bv1, farthest + reach));
      visit(box);
    }
}

/// Calls visit(box) with the world box that the lines of sight through each
/// tile of kTile x kTile pixels span, from its nearest reading less the reach
/// to its farthest plus the reach (a box for parallel rays, a frustum's for a
/// camera); tiles share their last row and column.
template <typename Visit>
void forEachTileBox(const RangeMap& m, double reach, const Visit& visit) {
  forEachTileBoxOfRows(m, reach, 0, tileRows(m), visit);
}

}  // namespace

namespace {

/// The boxes of leaves (origins divided by the leaf's width) that the tiles
/// of each band of kRowsPerBand rows of tiles reach (forEachTileBox), per
/// band, worked out in parallel over the bands.
std::vector<std::vector<openvdb::CoordBBox>> boxesOfLeavesPerBand(const RangeMap& m, double voxelSize, double reach) {
  constexpr int kRowsPerBand = 8;
  const int bands = (tileRows(m) + kRowsPerBand - 1) / kRowsPerBand;
  std::vector<std::vector<openvdb::CoordBBox>> boxes(static_cast<std::size_t>(bands));
  parallelFor(boxes.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      const int first = static_cast<int>(b) * kRowsPerBand;
      forEachTileBoxOfRows(m, reach, first, first + kRowsPerBand, [&](const openvdb::BBoxd& box) {
        boxes[b].emplace_back(Coord::floor(box.min() / (voxelSize * kLeafNodeWidth)),
                              Coord::floor(box.max() / (voxelSize * kLeafNodeWidth)));
      });
    }
  });
  return boxes;
}

/// The origins (in voxels) of the leaves in `boxes`, sorted, each once: bits
/// of a dense block over `bounds` (the boxes' bounds), read in the order of
/// Coord's comparison (x, then y, then z).
std::vector<Coord> leavesOfDenseBlock(const std::vector<std::vector<openvdb::CoordBBox>>& boxes,
                                      const openvdb::CoordBBox& bounds) {
  const openvdb::Coord dim = bounds.dim();
  const auto bitOf = [&](const Coord& leaf) {
    const Coord at = leaf - bounds.min();
    return (static_cast<std::size_t>(at.x()) * static_cast<std::size_t>(dim.y()) + static_cast<std::size_t>(at.y())) *
               static_cast<std::size_t>(dim.z()) +
           static_cast<std::size_t>(at.z());
  };
  std::vector<std::uint64_t> marked((static_cast<std::size_t>(bounds.volume()) + 63) / 64, 0);
  // A box's leaves of one x and y are a run of neighbouring bits (z varies fastest): marked a word at a time.
  const auto markRun = [&marked](std::size_t first, std::size_t last) {
    for (std::size_t word = first >> 6; word <= last >> 6; ++word) {
      const std::size_t from = word == first >> 6 ? first & 63 : 0, to = word == last >> 6 ? last & 63 : 63;
      marked[word] |= (~std::uint64_t(0) >> (63 - to)) & (~std::uint64_t(0) << from);
    }
  };
  for (const std::vector<openvdb::CoordBBox>& band : boxes)
    for (const openvdb::CoordBBox& box : band)
      for (int x = box.min().x(); x <= box.max().x(); ++x)
        for (int y = box.min().y(); y <= box.max().y(); ++y)
          markRun(bitOf(Coord(x, y, box.min().z())), bitOf(Coord(x, y, box.max().z())));
  std::size_t count = 0;
  for (const std::uint64_t word : marked) count += openvdb::util::CountOn(static_cast<openvdb::Index64>(word));
  std::vector<Coord> leaves;
  leaves.reserve(count);
  const std::size_t perX = static_cast<std::size_t>(dim.y()) * static_cast<std::size_t>(dim.z());
  for (std::size_t word = 0; word < marked.size(); ++word)
    for (std::uint64_t bits = marked[word]; bits != 0; bits &= bits - 1) {
      const std::size_t bit = word * 64 + openvdb::util::FindLowestOn(static_cast<openvdb::Index64>(bits));
      const int x = bounds.min().x() + static_cast<int>(bit / perX);
      const int y = bounds.min().y() + static_cast<int>(bit % perX / static_cast<std::size_t>(dim.z()));
      const int z = bounds.min().z() + static_cast<int>(bit % static_cast<std::size_t>(dim.z()));
      leaves.emplace_back(x * kLeafNodeWidth, y * kLeafNodeWidth, z * kLeafNodeWidth);
    }
  return leaves;
}

/// The same from sparse trees of marks, for boxes whose bounds span more
/// leaves than a dense block should hold: each band marks its own tree in
/// parallel, joined in the order of the bands.
std::vector<Coord> leavesOfSparseMarks(const std::vector<std::vector<openvdb::CoordBBox>>& boxes) {
  std::vector<openvdb::MaskTree> marked(boxes.size());
  parallelFor(marked.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      openvdb::tree::ValueAccessor<openvdb::MaskTree, false> marks(marked[b]);  // its band's own tree: not registered
      for (const openvdb::CoordBBox& box : boxes[b])
        for (auto leaf = box.beginZYX(); leaf; ++leaf) marks.setValueOn(*leaf);
    }
  });
  openvdb::MaskTree coarse;
  for (openvdb::MaskTree& band : marked) coarse.topologyUnion(band);
  std::vector<Coord> leaves;
  leaves.reserve(coarse.activeVoxelCount());
  for (auto it = coarse.cbeginValueOn(); it; ++it) {
    const Coord& block = it.getCoord();  // scaled, not shifted: the coordinates may be negative
    leaves.emplace_back(block.x() * kLeafNodeWidth, block.y() * kLeafNodeWidth, block.z() * kLeafNodeWidth);
  }
  std::sort(leaves.begin(), leaves.end());
  return leaves;
}

}  // namespace

std::vector<Coord> leavesReached(const RangeMap& m, double voxelSize, double reach, double mostDenseLeaves) {
  const std::vector<std::vector<openvdb::CoordBBox>> boxes = boxesOfLeavesPerBand(m, voxelSize, reach);
  openvdb::CoordBBox bounds;
  for (const std::vector<openvdb::CoordBBox>& band : boxes)
    for (const openvdb::CoordBBox& box : band) bounds.expand(box);
  if (bounds.empty()) return {};
  // In doubles: the bounds of a far-reaching map may span more leaves than an integer counts.
  const openvdb::Vec3d dim = bounds.max().asVec3d() - bounds.min().asVec3d() + openvdb::Vec3d(1.0);
  if (dim.x() * dim.y() * dim.z() <= mostDenseLeaves) return leavesOfDenseBlock(boxes, bounds);
  return leavesOfSparseMarks(boxes);
}

namespace {

/// The first and last leaves (origin / leaf width) whose origins a Coord holds.
constexpr double kFirstLeaf = static_cast<double>(std::numeric_limits<openvdb::Int32>::min() / kLeafNodeWidth);
constexpr double kLastLeaf = static_cast<double>((std::numeric_limits<openvdb::Int32>::max() - kLeafNodeWidth + 1) /
                                                 kLeafNodeWidth);

}  // namespace

double leafMarks(const RangeMap& m, double voxelSize, double reach, openvdb::BBoxd& reached, double xMin,
                 double xMax) {
  double marks = 0.0;
  const double leaf = voxelSize * kLeafNodeWidth;
  forEachTileBox(m, reach, [&](openvdb::BBoxd box) {
    // A box reaching infinity keeps its NaN or infinite bounds: its marks stay unbounded.
    if (box.max().x() < xMin || box.min().x() > xMax) return;
    box.min().x() = std::max(box.min().x(), xMin);
    box.max().x() = std::min(box.max().x(), xMax);
    reached.expand(box);
    double cells = 1.0;  // in doubles: a box may span more leaves than an int counts
    for (int axis = 0; axis < 3; ++axis) {
      const double first = std::floor(box.min()[axis] / leaf), last = std::floor(box.max()[axis] / leaf);
      // A leaf whose origin no Coord holds cannot be marked: unbounded.
      if (!(first >= kFirstLeaf && last <= kLastLeaf)) cells = HUGE_VAL;
      cells *= last - first + 1.0;
    }
    marks += cells;
  });
  return marks;
}

double cubeBallRadius(double voxelSize, int dim) { return 0.5 * std::sqrt(3.0) * (voxelSize * (dim - 1)); }

namespace {

/// Where the voxel centres of the cube of `dim` voxels a side at `origin` lie
/// in a map's frame: the bounds of its eight corners' depths, and of the pixel
/// coordinates of those in front of the map (all of them for parallel rays).
struct CubeFootprint {
  int inFront = 0;  ///< corners in front of the camera
  double u0 = 1e300, v0 = 1e300, u1 = -1e300, v1 = -1e300, z0 = 1e300, z1 = -1e300;
};

/// A spherical map's footprint of the ball of `radius` around `centre` (map
/// frame): ranges from its nearest to its farthest point, elevations and
/// azimuths within its angular radius. A ball around the scanner, over a pole,
/// or across the first column of a map that closes the turn has no bounded
/// footprint (inFront < 8).
CubeFootprint sphericalFootprint(const RangeMap& m, const Vec3d& centre, double radius) {
  CubeFootprint f;
  const double distance = centre.length();
  f.z0 = std::max(0.0, distance - radius);
  f.z1 = distance + radius;
  if (!(distance > radius * (1.0 + 1e-9))) {
    f.inFront = 4;
    return f;
  }
  const SphericalProjection& p = m.sphericalProjection();
  const double angularRadius = std::asin(radius / distance);
  const double elevation = std::atan2(centre.z(), std::hypot(centre.x(), centre.y()));
  if (std::fabs(elevation) + angularRadius >= 0.5 * M_PI) {
    f.inFront = 4;
    return f;
  }
  const double halfAzimuth = std::asin(std::sin(angularRadius) / std::cos(elevation)) / std::fabs(p.azimuthStep);
  const double column = m.project(centre).x();
  f.u0 = column - halfAzimuth;
  f.u1 = column + halfAzimuth;
  // Across the first column (its border included, at the turn's end): no bounded footprint.
  const bool wrapsIntoTheMap = (f.u0 < 0.0 && f.u0 + m.azimuthPeriod() <= m.width() - 1 + m.borderReach()) ||
                               f.u1 >= m.azimuthPeriod() - m.borderReach();
  f.inFront = wrapsIntoTheMap ? 4 : 8;
  const double r0 = rowOfElevation(p, elevation - angularRadius);
  const double r1 = rowOfElevation(p, elevation + angularRadius);
  f.v0 = std::min(r0, r1);
  f.v1 = std::max(r0, r1);
  return f;
}

/// Whether `m` surely sees none of the voxels of the cube of `dim` a side at
/// `origin`: the ball around their centres lies beside its sight.
bool missesCube(const RangeMap& m, const Coord& origin, int dim, double voxelSize) {
  const double half = 0.5 * (dim - 1);
  return m.missesBall((origin.asVec3d() + Vec3d(half)) * voxelSize, cubeBallRadius(voxelSize, dim));
}

CubeFootprint cubeFootprint(const RangeMap& m, const Coord& origin, double voxelSize, int dim = kLeafNodeWidth) {
  const openvdb::math::Mat4d& toMap = m.worldToMap();
  const Vec3d base = toMap.transform(origin.asVec3d() * voxelSize);
  const double span = voxelSize * (dim - 1);
  if (!m.projection().keepsLinesStraight())
    return sphericalFootprint(m, base + toMap.transform3x3(Vec3d(0.5 * span)), cubeBallRadius(voxelSize, dim));
  CubeFootprint f;
  for (int c = 0; c < 8; ++c) {
    const Vec3d q = base + toMap.transform3x3(Vec3d((c & 1) * span, ((c >> 1) & 1) * span, (c >> 2) * span));
    f.z0 = std::min(f.z0, q.z());
    f.z1 = std::max(f.z1, q.z());
    if (!m.canProject(q)) continue;  // behind the camera (a station's were answered above)
    ++f.inFront;
    const openvdb::math::Vec2d uv = m.project(q);
    f.u0 = std::min(f.u0, uv.x());
    f.u1 = std::max(f.u1, uv.x());
    f.v0 = std::min(f.v0, uv.y());
    f.v1 = std::max(f.v1, uv.y());
  }
  return f;
}

/// The slack a footprint's tests leave to the voxels, for ties within
/// rounding: in pixels, and in depth for a distance `distance` from it.
constexpr double kPixelSlack = 1e-6;
double depthSlack(const CubeFootprint& f, double distance) {
  return 1e-9 * (std::fabs(f.z0) + std::fabs(f.z1) + distance);
}

}  // namespace

bool leafMayBeReached(const UsableSpans& spans, const Coord& origin, double voxelSize, double reach) {
  return cubeMayBeReached(spans, origin, kLeafNodeWidth, voxelSize, reach);
}

bool cubeMayBeReached(const UsableSpans& spans, const Coord& origin, int dim, double voxelSize, double reach) {
  const CubeFootprint f = cubeFootprint(spans.map(), origin, voxelSize, dim);
  if (f.inFront < 8) return true;  // straddles the camera plane
  // A voxel is reached only from the usable cell it projects into, whose
  // reading lies within the reach of its depth.
  const double slack = depthSlack(f, reach);
  return spans.meet(f.u0 - kPixelSlack, f.v0 - kPixelSlack, f.u1 + kPixelSlack, f.v1 + kPixelSlack,
                    f.z0 - reach - slack, f.z1 + reach + slack);
}

std::uint8_t leafCubesMayBeReached(const UsableSpans& spans, const Coord& origin, double voxelSize, double reach) {
  constexpr int kHalf = kLeafNodeWidth / 2;
  std::uint8_t reached = 0;
  for (int c = 0; c < 8; ++c) {
    const Coord corner = origin.offsetBy(((c >> 2) & 1) * kHalf, ((c >> 1) & 1) * kHalf, (c & 1) * kHalf);
    if (cubeMayBeReached(spans, corner, kHalf, voxelSize, reach)) reached = static_cast<std::uint8_t>(reached | (1 << c));
  }
  return reached;
}

std::optional<RangeMap::Sight> leafSight(const RangeMap& m, const Coord& origin, double voxelSize, double margin) {
  return cubeSight(m, origin, kLeafNodeWidth, voxelSize, margin);
}

namespace {

/// Pixels at most that cubeSight reads one by one when the blocks' bounds do
/// not decide: a cube's footprint can be cheaper to read than its voxels' sights.
constexpr int kMostPixelsRead = 1024;

/// What a footprint whose four pixels around every voxel have no reading says:
/// unknown to every voxel, unless a pixel without a reading may be a miss.
std::optional<RangeMap::Sight> withoutReadings(const RangeMap& m) {
  if (m.missesAreEmpty()) return std::nullopt;
  return RangeMap::Sight::kUnknown;
}

/// What readings from lo to hi at every pixel of a footprint at depths z0 to
/// z1 say of every voxel, if the same.
std::optional<RangeMap::Sight> behindOrInFront(double lo, double hi, double z0, double z1, double margin,
                                               double slack) {
  if (z0 - hi > margin + slack) return RangeMap::Sight::kBehind;
  if (z1 - lo < -margin - slack) return RangeMap::Sight::kEmpty;
  return std::nullopt;
}

/// The same from the pixels i0 to i1 and j0 to j1 themselves, read until one
/// says other than the first: exact where the blocks around them hold a hole
/// or readings far from theirs.
std::optional<RangeMap::Sight> sightOfPixels(const RangeMap& m, int i0, int j0, int i1, int j1, double z0, double z1,
                                             double margin, double slack) {
  const float first = m.reading(i0, j0);
  if (!(first == first))
    return m.everyPixel(i0, j0, i1, j1, [](float r) { return !(r == r); }) ? withoutReadings(m) : std::nullopt;
  const std::optional<RangeMap::Sight> s = behindOrInFront(first, first, z0, z1, margin, slack);
  if (s && m.everyPixel(i0, j0, i1, j1, [&](float r) { return behindOrInFront(r, r, z0, z1, margin, slack) == s; }))
    return s;
  return std::nullopt;
}

}  // namespace

std::optional<RangeMap::Sight> cubeSight(const RangeMap& m, const Coord& origin, int dim, double voxelSize,
                                         double margin) {
  using Sight = RangeMap::Sight;
  // Most cubes lie beside most maps' sight: a few products say so, before
  // the corners are projected.
  if (missesCube(m, origin, dim, voxelSize)) return Sight::kOutside;
  CubeFootprint f = cubeFootprint(m, origin, voxelSize, dim);
  double &u0 = f.u0, &v0 = f.v0, &u1 = f.u1, &v1 = f.v1;
  const double z0 = f.z0, z1 = f.z1;
  const int inFront = f.inFront;
  if (inFront == 0) return Sight::kOutside;  // wholly behind the camera
  if (inFront < 8) return std::nullopt;      // straddles the camera plane: the projection is unbounded
  // In front of a camera, or along parallel rays, the leaf projects into the
  // convex hull of its corners' projections; its depths lie between its
  // corners'. A little slack leaves ties within rounding to the voxels.
  const double slack = depthSlack(f, margin);
  u0 -= kPixelSlack;
  v0 -= kPixelSlack;
  u1 += kPixelSlack;
  v1 += kPixelSlack;
  if (u1 < 0.0 || v1 < 0.0 || u0 > m.width() - 1 || v0 > m.height() - 1) return Sight::kOutside;
  if (u0 < 0.0 || v0 < 0.0 || u1 > m.width() - 1 || v1 > m.height() - 1) return std::nullopt;
  // The four pixels around every voxel: from floor(u0) to floor(u1) + 1.
  const int i0 = static_cast<int>(std::floor(u0)), j0 = static_cast<int>(std::floor(v0));
  const int i1 = static_cast<int>(std::floor(u1)) + 1, j1 = static_cast<int>(std::floor(v1)) + 1;
  double lo, hi;
  bool complete = false;
  if (!m.readingBounds(i0, j0, i1, j1, lo, hi, &complete)) return withoutReadings(m);
  if (complete)
    if (const std::optional<Sight> s = behindOrInFront(lo, hi, z0, z1, margin, slack)) return s;
  // The blocks around the footprint hold a hole or readings beyond it: its
  // own pixels, if few.
  if ((i1 - i0 + 1) * (j1 - j0 + 1) > kMostPixelsRead) return std::nullopt;
  return sightOfPixels(m, i0, j0, i1, j1, z0, z1, margin, slack);
}

}  // namespace levelfuse::detail
