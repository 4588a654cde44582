// levelfuse: exact distances from points to a triangle mesh.
//
// The triangles are binned into cubic cells held in a sparse OpenVDB tree, so
// memory grows with the surface, never with its bounding box. A query visits
// rings of cells around its point until no unvisited cell can hold a nearer
// triangle; a point farther out (a stray scan point, a part of a scene the
// mesh lost) descends the tree of cells instead, nearest nodes first, skipping
// every node no nearer than the best triangle found. Queries are read-only
// and may run in parallel.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <vector>

namespace levelfuse {

/// Distance from `p` to the closed triangle (a, b, c); degenerate triangles
/// (segments, points) are measured correctly too.
double pointTriangleDistance(const openvdb::Vec3d& p, const openvdb::Vec3d& a, const openvdb::Vec3d& b,
                             const openvdb::Vec3d& c);

class NearestTriangle {
 public:
  /// `xyz`: three coordinates per vertex; `triangles`: three vertex indices
  /// each. Both are referred to, not copied: they must outlive the index. Throws std::invalid_argument for no triangles, an index past the
  /// vertices, or a vertex that is not finite.
  NearestTriangle(const std::vector<float>& xyz, const std::vector<std::uint32_t>& triangles);

  /// Distance from `p` to the nearest point of the mesh (world units).
  double distance(const openvdb::Vec3d& p) const;

  double cellSize() const { return mCellSize; }

 private:
  openvdb::Vec3d vertex(std::uint32_t i) const {
    return openvdb::Vec3d(mXyz[3 * i], mXyz[3 * i + 1], mXyz[3 * i + 2]);
  }
  double triangleDistance(const openvdb::Vec3d& p, std::uint32_t t) const {
    return pointTriangleDistance(p, vertex(mTriangles[3 * t]), vertex(mTriangles[3 * t + 1]),
                                 vertex(mTriangles[3 * t + 2]));
  }

  const std::vector<float>& mXyz;
  const std::vector<std::uint32_t>& mTriangles;
  double mCellSize = 1.0;
  /// Per occupied cell: the range [begin, end) of its entries in mBinned.
  openvdb::Vec2ITree mCells;
  std::vector<std::uint32_t> mBinned;
  /// Triangles spanning too many cells to bin: measured by every query.
  std::vector<std::uint32_t> mOversized;
};

}  // namespace levelfuse
