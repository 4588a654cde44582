// levelfuse: a surface measured against held-out depth frames.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/geometry/NearestTriangle.h>
#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/recon/HeldOutFrames.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace levelfuse {

namespace {

void checkArguments(const std::vector<RangeMap>& frames, const HeldOutOptions& options) {
  if (frames.empty()) throw std::invalid_argument("measureHeldOutFrames: no held-out frames");
  if (options.stride < 1) throw std::invalid_argument("measureHeldOutFrames: the stride must be at least 1");
  for (const double threshold : options.thresholds)
    if (!(threshold > 0.0) || !std::isfinite(threshold))
      throw std::invalid_argument("measureHeldOutFrames: a threshold must be a positive distance, not " +
                                  std::to_string(threshold));
  for (const RangeMap& frame : frames)
    if (frame.kind() != RangeMap::Kind::kPinhole)
      throw std::invalid_argument("measureHeldOutFrames: the frame '" + frame.name() +
                                  "' is not a depth camera's (pinhole) map");
}

/// The world points of a frame's valid pixels, every `stride`-th in each direction.
std::vector<openvdb::Vec3d> backProject(const RangeMap& frame, int stride) {
  std::vector<openvdb::Vec3d> points;
  for (int v = 0; v < frame.height(); v += stride)
    for (int u = 0; u < frame.width(); u += stride)
      if (frame.valid(u, v)) points.push_back(frame.readingPoint(u, v));
  return points;
}

}  // namespace

HeldOutAccuracy measureHeldOutFrames(const TriangleMesh& mesh, const std::vector<RangeMap>& frames,
                                     const HeldOutOptions& options) {
  checkArguments(frames, options);
  if (mesh.triangleCount() == 0) throw std::invalid_argument("measureHeldOutFrames: the mesh has no triangles");
  const NearestTriangle nearest(mesh.xyz, mesh.triangles);
  // One frame's points at a time: the distances are kept, the points are not.
  std::vector<double> distances;
  for (const RangeMap& frame : frames) {
    const std::vector<openvdb::Vec3d> points = backProject(frame, options.stride);
    const std::size_t first = distances.size();
    distances.resize(first + points.size());
    parallelFor(points.size(), 1024, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) distances[first + i] = nearest.distance(points[i]);
    });
  }
  HeldOutAccuracy accuracy;
  accuracy.thresholds = options.thresholds;
  for (std::size_t k = 0; k < options.thresholds.size(); ++k) {
    std::size_t near = 0;
    for (const double d : distances) near += d <= options.thresholds[k];
    accuracy.within[k] = distances.empty() ? 0.0 : static_cast<double>(near) / static_cast<double>(distances.size());
  }
  accuracy.distances = summariseDistances(std::move(distances));
  return accuracy;
}

HeldOutAccuracy measureHeldOutFrames(const openvdb::FloatGrid& levelSet, const std::vector<RangeMap>& frames,
                                     const HeldOutOptions& options) {
  requireLevelSet(levelSet, "measureHeldOutFrames");
  checkArguments(frames, options);
  const TriangleMesh mesh = meshFromLevelSet(levelSet);
  if (mesh.triangleCount() == 0)
    throw std::invalid_argument("measureHeldOutFrames: the level set '" + levelSet.getName() + "' has no zero set");
  return measureHeldOutFrames(mesh, frames, options);
}

FrameSplit splitFrames(std::size_t count, int every, int offset) {
  if (every < 1 || offset < 0 || offset >= every)
    throw std::invalid_argument("splitFrames: needs 0 <= offset < every, not offset " + std::to_string(offset) +
                                " and every " + std::to_string(every));
  FrameSplit split;
  for (std::size_t i = 0; i < count; ++i)
    (i % static_cast<std::size_t>(every) == static_cast<std::size_t>(offset) ? split.heldOut : split.reconstruction)
        .push_back(i);
  return split;
}

}  // namespace levelfuse
