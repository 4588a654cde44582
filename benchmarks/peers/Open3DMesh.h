// An Open3D triangle mesh as a peer's plain vectors (for the Open3D peers' own
// translation units only).
#pragma once

#include "peers/PeerMesh.h"

#include <open3d/geometry/TriangleMesh.h>

namespace levelfuse::peers {

inline PeerMesh fromOpen3D(const open3d::geometry::TriangleMesh& mesh) {
  PeerMesh out;
  out.xyz.reserve(3 * mesh.vertices_.size());
  for (const Eigen::Vector3d& v : mesh.vertices_)
    for (int k = 0; k < 3; ++k) out.xyz.push_back(static_cast<float>(v[k]));
  out.triangles.reserve(3 * mesh.triangles_.size());
  for (const Eigen::Vector3i& t : mesh.triangles_)
    for (int k = 0; k < 3; ++k) out.triangles.push_back(static_cast<std::uint32_t>(t[k]));
  return out;
}

}  // namespace levelfuse::peers
