// levelfuse: the zero set of a level set as a triangle mesh.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <vector>

namespace levelfuse {

/// A triangle mesh in world units: xyz holds three floats per vertex,
/// triangles three vertex indices each, counter-clockwise seen from outside;
/// rgb, if not empty, three bytes (red, green, blue from 0 to 255) per vertex.
struct TriangleMesh {
  std::vector<float> xyz;
  std::vector<std::uint32_t> triangles;
  std::vector<std::uint8_t> rgb;

  bool hasColours() const { return !rgb.empty(); }
  std::size_t vertexCount() const { return xyz.size() / 3; }
  std::size_t triangleCount() const { return triangles.size() / 3; }
  /// Enclosed volume (positive for a closed, outward-facing mesh) and area.
  double volume() const;
  double area() const;
};

/// The zero set of `levelSet` by OpenVDB's volumeToMesh (quads split into
/// triangles), with `adaptivity` in [0, 1] (0: uniform, as fine as the grid).
TriangleMesh meshFromLevelSet(const openvdb::FloatGrid& levelSet, double adaptivity = 0.0);
/// The same, its polygons made only in the voxels `within` marks (active):
/// the part of a surface a mask keeps, without meshing the rest.
TriangleMesh meshFromLevelSet(const openvdb::FloatGrid& levelSet, double adaptivity, const openvdb::BoolGrid& within);

/// A closed mesh as an OpenVDB level set of `voxelSize` (world units) with a
/// narrow band of `halfWidth` voxels on either side, by meshToLevelSet: how a
/// peer's mesh is held to the rulers of a level set.
openvdb::FloatGrid::Ptr levelSetFromMesh(const TriangleMesh& mesh, double voxelSize, float halfWidth = 3.0f);

}  // namespace levelfuse
