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

TriangleMesh meshFromLevelSet(const openvdb::FloatGrid& levelSet, double adaptivity) {
  requireLevelSet(levelSet, "meshFromLevelSet");
  if (!(adaptivity >= 0.0 && adaptivity <= 1.0))
    throw std::invalid_argument("meshFromLevelSet: the adaptivity must lie in [0, 1]");
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(levelSet, points, triangles, quads, 0.0, adaptivity);
  TriangleMesh mesh;
  mesh.xyz.reserve(points.size() * 3);
  for (const openvdb::Vec3s& p : points) mesh.xyz.insert(mesh.xyz.end(), {p.x(), p.y(), p.z()});
  mesh.triangles.reserve(3 * (triangles.size() + 2 * quads.size()));
  // volumeToMesh orders the corners of a level set's polygons clockwise seen
  // from outside: reversed here.
  for (const openvdb::Vec3I& t : triangles) mesh.triangles.insert(mesh.triangles.end(), {t[2], t[1], t[0]});
  for (const openvdb::Vec4I& q : quads) {
    mesh.triangles.insert(mesh.triangles.end(), {q[2], q[1], q[0]});
    mesh.triangles.insert(mesh.triangles.end(), {q[3], q[2], q[0]});
  }
  return mesh;
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
