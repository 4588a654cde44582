// levelfuse: the accuracy of a surface on depth frames it was not made from.
//
// A depth camera has no ground truth, but it has more frames than a
// reconstruction needs: build from some, hold the others out, back-project
// every valid depth pixel of a held-out frame with its pose, and measure each
// point's exact distance to the surface's triangles. Points the surface never
// comes near (parts of the scene it lost) count with their full distance.
#pragma once

#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>

#include <array>
#include <cstddef>
#include <vector>

namespace levelfuse {

struct HeldOutOptions {
  /// Every `stride`-th pixel in each direction of each frame (every stride^2-th pixel).
  int stride = 1;
  /// Distances (world units) whose shares `HeldOutAccuracy::within` reports: 1, 2 and 5 cm by default.
  std::array<double, 3> thresholds{0.01, 0.02, 0.05};
};

struct HeldOutAccuracy {
  /// The distances' summary: `readings` points measured, their mean, rms,
  /// median, p90 and p99 (world units).
  DataFit distances;
  std::array<double, 3> thresholds{};  ///< as given in the options
  std::array<double, 3> within{};      ///< fraction of the points within each threshold of the surface
};

/// Measures `mesh` against the held-out `frames` (pinhole range maps): the
/// exact distance from each back-projected valid pixel to the nearest
/// triangle. Throws std::invalid_argument for no frames, a frame that is not
/// a pinhole map, a stride below 1, a threshold that is not positive, or a
/// mesh without triangles. No valid pixel: zero points, zeros throughout.
HeldOutAccuracy measureHeldOutFrames(const TriangleMesh& mesh, const std::vector<RangeMap>& frames,
                                     const HeldOutOptions& options = {});
/// The same for the zero set of an OpenVDB level set, meshed by meshFromLevelSet.
HeldOutAccuracy measureHeldOutFrames(const openvdb::FloatGrid& levelSet, const std::vector<RangeMap>& frames,
                                     const HeldOutOptions& options = {});

/// Positions 0 .. count-1 of a sequence of frames split in two: every
/// `every`-th position from `offset` on is held out, the others reconstruct.
/// Throws std::invalid_argument unless 0 <= offset < every.
struct FrameSplit {
  std::vector<std::size_t> reconstruction, heldOut;
};
FrameSplit splitFrames(std::size_t count, int every, int offset = 0);

}  // namespace levelfuse
