// levelfuse: exact distances from points to a triangle mesh.

#include <levelfuse/geometry/NearestTriangle.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace levelfuse {

namespace {

using openvdb::Coord;
using openvdb::Vec3d;

/// Rings of cells a query visits before it searches the tree of cells.
constexpr int kMaxRing = 8;
/// A triangle whose bounding box spans more cells than this is not binned.
constexpr long kMaxCellsPerTriangle = 512;

/// Distance from `p` to the box of the index cells `box` (inclusive) of size `cell`.
double boxDistance(const Vec3d& p, const openvdb::CoordBBox& box, double cell) {
  double squared = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double lo = box.min()[k] * cell, hi = (box.max()[k] + 1.0) * cell;
    const double d = p[k] < lo ? lo - p[k] : (p[k] > hi ? p[k] - hi : 0.0);
    squared += d * d;
  }
  return std::sqrt(squared);
}

/// Branch and bound through the tree of cells: children in order of their
/// distance from `p`, none visited that lies no nearer than `best`. A
/// triangle is binned in every cell its bounding box meets, so its nearest
/// point to `p` lies in one of its own cells: skipping the far cells is exact.
template <typename NodeT, typename MeasureCell>
void nearestInNode(const NodeT& node, const Vec3d& p, double cell, double& best, const MeasureCell& measureCell) {
  if constexpr (NodeT::LEVEL == 0) {
    for (auto it = node.cbeginValueOn(); it; ++it)
      if (boxDistance(p, openvdb::CoordBBox(it.getCoord(), it.getCoord()), cell) < best) measureCell(*it);
  } else {
    using ChildT = typename NodeT::ChildNodeType;
    std::vector<std::pair<double, const ChildT*>> children;
    for (auto it = node.cbeginChildOn(); it; ++it)
      children.emplace_back(boxDistance(p, it->getNodeBoundingBox(), cell), &*it);
    std::sort(children.begin(), children.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [distance, child] : children) {
      if (distance >= best) break;
      nearestInNode(*child, p, cell, best, measureCell);
    }
  }
}

bool coordLess(const std::pair<Coord, std::uint32_t>& a, const std::pair<Coord, std::uint32_t>& b) {
  if (a.first != b.first) return a.first < b.first;
  return a.second < b.second;
}

}  // namespace

double pointTriangleDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  // The closest point by the triangle's Voronoi regions (Ericson, Real-Time
  // Collision Detection, 5.1.5), in the order vertex, edge, face.
  const Vec3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return ap.length();
  const Vec3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return bp.length();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return (p - (a + ab * (d1 / (d1 - d3)))).length();
  const Vec3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return cp.length();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return (p - (a + ac * (d2 / (d2 - d6)))).length();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).length();
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) {  // degenerate: the nearest of the three edges
    const auto segment = [&](const Vec3d& s, const Vec3d& e) {
      const Vec3d d = e - s;
      const double t = d.lengthSqr() > 0.0 ? std::clamp((p - s).dot(d) / d.lengthSqr(), 0.0, 1.0) : 0.0;
      return (p - (s + d * t)).length();
    };
    return std::min({segment(a, b), segment(b, c), segment(c, a)});
  }
  return (p - (a + ab * (vb / sum) + ac * (vc / sum))).length();
}

NearestTriangle::NearestTriangle(const std::vector<float>& xyz, const std::vector<std::uint32_t>& triangles)
    : mXyz(xyz), mTriangles(triangles), mCells(openvdb::Vec2i(-1, -1)) {
  const std::size_t count = triangles.size() / 3, vertices = xyz.size() / 3;
  if (count == 0 || triangles.size() % 3 != 0 || xyz.size() % 3 != 0)
    throw std::invalid_argument("NearestTriangle: the mesh has no triangles, or arrays not in threes");
  if (count > static_cast<std::size_t>(std::numeric_limits<std::uint32_t>::max()))
    throw std::invalid_argument("NearestTriangle: more triangles than 32-bit indices hold");
  for (float v : xyz)
    if (!std::isfinite(v)) throw std::invalid_argument("NearestTriangle: a vertex is not finite");
  for (std::uint32_t i : triangles)
    if (i >= vertices) throw std::invalid_argument("NearestTriangle: a triangle names a missing vertex");

  // Cells twice the mean edge: a typical triangle falls into one to eight.
  double edges = 0.0;
  for (std::size_t t = 0; t < count; ++t)
    for (int e = 0; e < 3; ++e)
      edges += (vertex(triangles[3 * t + e]) - vertex(triangles[3 * t + (e + 1) % 3])).length();
  mCellSize = 2.0 * edges / (3.0 * static_cast<double>(count));
  if (!(mCellSize > 0.0)) mCellSize = 1.0;  // every triangle is a point: any size works

  std::vector<std::pair<Coord, std::uint32_t>> binned;
  binned.reserve(2 * count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const Vec3d a = vertex(triangles[3 * t]), b = vertex(triangles[3 * t + 1]), c = vertex(triangles[3 * t + 2]);
    const Coord lo = Coord::floor(openvdb::math::minComponent(a, openvdb::math::minComponent(b, c)) / mCellSize);
    const Coord hi = Coord::floor(openvdb::math::maxComponent(a, openvdb::math::maxComponent(b, c)) / mCellSize);
    const long cells = (hi.x() - lo.x() + 1L) * (hi.y() - lo.y() + 1L) * (hi.z() - lo.z() + 1L);
    if (cells > kMaxCellsPerTriangle) {
      mOversized.push_back(t);
      continue;
    }
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int z = lo.z(); z <= hi.z(); ++z) binned.emplace_back(Coord(x, y, z), t);
  }
  std::sort(binned.begin(), binned.end(), coordLess);
  mBinned.resize(binned.size());
  openvdb::tree::ValueAccessor<openvdb::Vec2ITree> cells(mCells);
  for (std::size_t i = 0; i < binned.size();) {
    std::size_t end = i;
    while (end < binned.size() && binned[end].first == binned[i].first) {
      mBinned[end] = binned[end].second;
      ++end;
    }
    cells.setValueOn(binned[i].first, openvdb::Vec2i(static_cast<int>(i), static_cast<int>(end)));
    i = end;
  }
}

double NearestTriangle::distance(const Vec3d& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (std::uint32_t t : mOversized) best = std::min(best, triangleDistance(p, t));
  const auto measureCell = [&](const openvdb::Vec2i& range) {
    for (int i = range[0]; i < range[1]; ++i) best = std::min(best, triangleDistance(p, mBinned[i]));
  };
  openvdb::tree::ValueAccessor<const openvdb::Vec2ITree> cells(mCells);
  const Vec3d inCells = p / mCellSize;
  const bool addressable = std::fabs(inCells.x()) < 1e9 && std::fabs(inCells.y()) < 1e9 && std::fabs(inCells.z()) < 1e9;
  const Coord centre = addressable ? Coord::floor(inCells) : Coord();
  for (int ring = 0; addressable && ring <= kMaxRing; ++ring) {
    for (int x = -ring; x <= ring; ++x)
      for (int y = -ring; y <= ring; ++y) {
        const bool face = std::abs(x) == ring || std::abs(y) == ring;
        // Cells of the ring only: all of z on its faces, the two caps inside.
        for (int z = -ring; z <= ring; z += face || ring == 0 ? 1 : 2 * ring) {
          const Coord at = centre.offsetBy(x, y, z);
          openvdb::Vec2i range;
          if (cells.probeValue(at, range) && boxDistance(p, openvdb::CoordBBox(at, at), mCellSize) < best)
            measureCell(range);
        }
      }
    // Every triangle not yet seen lies in cells beyond this ring, at least
    // `ring` cells from p's own.
    if (best <= ring * mCellSize) return best;
  }
  if (addressable) {
    nearestInNode(mCells.root(), p, mCellSize, best, measureCell);
    return best;
  }
  const std::uint32_t count = static_cast<std::uint32_t>(mTriangles.size() / 3);
  for (std::uint32_t t = 0; t < count; ++t) best = std::min(best, triangleDistance(p, t));
  return best;
}

}  // namespace levelfuse
