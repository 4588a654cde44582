// A peer's triangle mesh as plain vectors, with no peer's or OpenVDB's header.
#pragma once

#include <cstdint>
#include <vector>

namespace levelfuse::peers {

struct PeerMesh {
  std::vector<float> xyz;                 ///< world, three per vertex
  std::vector<std::uint32_t> triangles;   ///< three vertex indices each
};

}  // namespace levelfuse::peers
