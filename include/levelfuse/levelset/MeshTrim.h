// levelfuse: a mesh without the parts a grid says to leave out, e.g. the parts
// of a surface no scan observed (recon/SurfaceWeight.h).
#pragma once

#include <levelfuse/levelset/Mesh.h>

#include <openvdb/openvdb.h>

namespace levelfuse {

/// The triangles of `mesh` at whose centre `weight` (interpolated trilinearly,
/// world units) is at least `minWeight`, and only the vertices they use,
/// renumbered in their old order: a valid indexed mesh, open where triangles
/// were dropped. Parallel and deterministic. Throws std::invalid_argument for
/// a `minWeight` that is not finite or a mesh whose indices are out of range.
TriangleMesh trimMesh(const TriangleMesh& mesh, const openvdb::FloatGrid& weight, double minWeight);

/// The voxels whose cells a triangle that trimMesh keeps may lie in: those
/// with a corner where `weight` is at least `minWeight`, as a mask for
/// meshFromLevelSet, so that a scene's unseen faces are not meshed only to
/// be trimmed.
openvdb::BoolGrid::Ptr voxelsToMesh(const openvdb::FloatGrid& weight, double minWeight);

}  // namespace levelfuse
