// levelfuse: meshes of level sets.

#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/RequireLevelSet.h>

#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <stdexcept>

namespace levelfuse {

namespace {

openvdb::Vec3d vertex(const TriangleMesh& mesh, std::uint32_t i) {
  return openvdb::Vec3d(mesh.xyz[3 * i], mesh.xyz[3 * i + 1], mesh.xyz[3 * i + 2]);
}

}  // namespace

double TriangleMesh::volume() const {
  double sum = 0.0;
  for (std::size_t t = 0; t < triangles.size(); t += 3)
    sum += vertex(*this, triangles[t]).dot(vertex(*this, triangles[t + 1]).cross(vertex(*this, triangles[t + 2])));
  return sum / 6.0;
}

double TriangleMesh::area() const {
  double sum = 0.0;
  for (std::size_t t = 0; t < triangles.size(); t += 3) {
    const openvdb::Vec3d a = vertex(*this, triangles[t]);
    sum += (vertex(*this, triangles[t + 1]) - a).cross(vertex(*this, triangles[t + 2]) - a).length();
  }
  return 0.5 * sum;
}

namespace {

/// The mesh a VolumeToMesh made: its points, and its polygons as triangles
/// turned to face outward (VolumeToMesh orders the corners of a level set's
/// polygons clockwise seen from outside).
TriangleMesh meshOf(const openvdb::tools::VolumeToMesh& mesher) {
  TriangleMesh mesh;
  mesh.xyz.reserve(mesher.pointListSize() * 3);
  for (std::size_t i = 0; i < mesher.pointListSize(); ++i) {
    const openvdb::Vec3s& p = mesher.pointList()[i];
    mesh.xyz.insert(mesh.xyz.end(), {p.x(), p.y(), p.z()});
  }
  const openvdb::tools::PolygonPoolList& pools = mesher.polygonPoolList();
  for (std::size_t n = 0; n < mesher.polygonPoolListSize(); ++n) {
    const openvdb::tools::PolygonPool& pool = pools[n];
    for (std::size_t t = 0; t < pool.numTriangles(); ++t) {
      const openvdb::Vec3I& c = pool.triangle(t);
      mesh.triangles.insert(mesh.triangles.end(), {c[2], c[1], c[0]});
    }
    for (std::size_t q = 0; q < pool.numQuads(); ++q) {
      const openvdb::Vec4I& c = pool.quad(q);
      mesh.triangles.insert(mesh.triangles.end(), {c[2], c[1], c[0]});
      mesh.triangles.insert(mesh.triangles.end(), {c[3], c[2], c[0]});
    }
  }
  return mesh;
}

void requireAdaptivity(double adaptivity) {
  if (!(adaptivity >= 0.0 && adaptivity <= 1.0))
    throw std::invalid_argument("meshFromLevelSet: the adaptivity must lie in [0, 1]");
}

}  // namespace

TriangleMesh meshFromLevelSet(const openvdb::FloatGrid& levelSet, double adaptivity) {
  requireLevelSet(levelSet, "meshFromLevelSet");
  requireAdaptivity(adaptivity);
  openvdb::tools::VolumeToMesh mesher(0.0, adaptivity);
  mesher(levelSet);
  return meshOf(mesher);
}

TriangleMesh meshFromLevelSet(const openvdb::FloatGrid& levelSet, double adaptivity, const openvdb::BoolGrid& within) {
  requireLevelSet(levelSet, "meshFromLevelSet");
  requireAdaptivity(adaptivity);
  openvdb::tools::VolumeToMesh mesher(0.0, adaptivity);
  mesher.setSurfaceMask(openvdb::BoolGrid::ConstPtr(&within, [](const openvdb::BoolGrid*) {}));
  mesher(levelSet);
  return meshOf(mesher);
}

openvdb::FloatGrid::Ptr levelSetFromMesh(const TriangleMesh& mesh, double voxelSize, float halfWidth) {
  const auto transform = openvdb::math::Transform::createLinearTransform(voxelSize);
  std::vector<openvdb::Vec3s> vertices(mesh.vertexCount());
  for (std::size_t i = 0; i < vertices.size(); ++i)
    vertices[i] = openvdb::Vec3s(mesh.xyz[3 * i], mesh.xyz[3 * i + 1], mesh.xyz[3 * i + 2]);
  std::vector<openvdb::Vec3I> triangles(mesh.triangleCount());
  for (std::size_t i = 0; i < triangles.size(); ++i)
    triangles[i] = openvdb::Vec3I(mesh.triangles[3 * i], mesh.triangles[3 * i + 1], mesh.triangles[3 * i + 2]);
  return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, vertices, triangles, halfWidth);
}

}  // namespace levelfuse
