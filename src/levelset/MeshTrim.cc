// levelfuse: trimming meshes by a weight grid.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/levelset/MeshTrim.h>

#include <levelfuse/levelset/detail/VoxelsWhere.h>

#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/Morphology.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <stdexcept>
#include <vector>

namespace levelfuse {

TriangleMesh trimMesh(const TriangleMesh& mesh, const openvdb::FloatGrid& weight, double minWeight) {
  if (!std::isfinite(minWeight)) throw std::invalid_argument("trimMesh: the weight to keep a triangle must be finite");
  const std::size_t vertices = mesh.vertexCount();
  for (const std::uint32_t index : mesh.triangles)
    if (index >= vertices)
      throw std::invalid_argument("trimMesh: a triangle names vertex " + std::to_string(index) + " of " +
                                  std::to_string(vertices) + " (not a valid indexed mesh)");
  if (mesh.hasColours() && mesh.rgb.size() != mesh.xyz.size())
    throw std::invalid_argument("trimMesh: a coloured mesh needs one colour per vertex");

  // Which triangles stay: the weight at their centres.
  std::vector<std::uint8_t> keep(mesh.triangleCount(), 0);
  parallelFor(keep.size(), 4096, [&](std::size_t begin, std::size_t end) {
    const openvdb::FloatGrid::ConstAccessor access = weight.getConstAccessor();
    const openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor, openvdb::tools::BoxSampler> sample(
        access, weight.transform());
    for (std::size_t t = begin; t < end; ++t) {
      openvdb::Vec3d centre(0.0);
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = mesh.triangles[3 * t + k];
        centre += openvdb::Vec3d(mesh.xyz[3 * v], mesh.xyz[3 * v + 1], mesh.xyz[3 * v + 2]);
      }
      keep[t] = sample.wsSample(centre / 3.0) >= minWeight;
    }
  });

  // The kept triangles and their vertices, renumbered in order.
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> renumbered(vertices, kUnused);
  TriangleMesh trimmed;
  for (std::size_t t = 0; t < keep.size(); ++t)
    if (keep[t])
      for (int k = 0; k < 3; ++k) renumbered[mesh.triangles[3 * t + k]] = 0;
  std::uint32_t next = 0;
  for (std::size_t v = 0; v < vertices; ++v) {
    if (renumbered[v] == kUnused) continue;
    renumbered[v] = next++;
    trimmed.xyz.insert(trimmed.xyz.end(), {mesh.xyz[3 * v], mesh.xyz[3 * v + 1], mesh.xyz[3 * v + 2]});
    if (mesh.hasColours())
      trimmed.rgb.insert(trimmed.rgb.end(), {mesh.rgb[3 * v], mesh.rgb[3 * v + 1], mesh.rgb[3 * v + 2]});
  }
  for (std::size_t t = 0; t < keep.size(); ++t)
    if (keep[t])
      for (int k = 0; k < 3; ++k) trimmed.triangles.push_back(renumbered[mesh.triangles[3 * t + k]]);
  return trimmed;
}

openvdb::BoolGrid::Ptr voxelsToMesh(const openvdb::FloatGrid& weight, double minWeight) {
  const float threshold = static_cast<float>(minWeight);
  auto mask = openvdb::BoolGrid::create(std::make_shared<openvdb::BoolTree>(
      detail::voxelsWhere<openvdb::BoolTree>(weight.tree(), [&](float w) { return w >= threshold; })));
  mask->setTransform(weight.transform().copy());
  // A cell is named by its lowest corner: the voxels one step below a
  // corner that is seen name cells it is a corner of.
  openvdb::tools::dilateActiveValues(mask->tree(), 1, openvdb::tools::NN_FACE_EDGE_VERTEX);
  return mask;
}

}  // namespace levelfuse
