// PoissonRecon as a benchmark peer: screened Poisson surface reconstruction
// (Kazhdan and Hoppe 2013) as Open3D ships it, from the same scans' points.
// This header includes no Open3D or OpenVDB header, so the two never meet in
// one translation unit.
#pragma once

#include "peers/PeerMesh.h"

#include <array>
#include <optional>
#include <vector>

namespace levelfuse::peers {

/// One range scan as PoissonRecon's users feed it: its points in the scan
/// frame, where its scanner is, and its placement in the world.
struct PoissonScan {
  std::vector<std::array<double, 3>> points;  ///< scan frame
  std::array<double, 3> towardScanner{0.0, 0.0, 1.0};  ///< scan frame
  /// Where the scanner stood (scan frame), if its rays fan out from one point
  /// (a terrestrial station): normals are turned toward it, not toward a direction.
  std::optional<std::array<double, 3>> scannerPosition;
  std::array<double, 16> scanToWorld{};  ///< row-major, points as row vectors: p_world = p * M
};

/// Normals estimated per scan from each point's 12 nearest neighbours and
/// turned toward its scanner (its direction, or its position), every scan placed in the world, then Poisson
/// reconstruction at octree `depth` (9: about 0.3 mm cells across the bunny)
/// on `threads` threads.
PeerMesh poissonReconstruct(const std::vector<PoissonScan>& scans, int depth, int threads);

}  // namespace levelfuse::peers
