// A scene scanned by terrestrial laser scanners: the synthetic room of
// shapes::Room (6 x 4 x 2.5 m, a table, a ball, a ring and a pillar) scanned
// from three tripods 1.5 m high by spherical scanners that sweep a whole turn
// and elevations from -75 to 75 degrees in steps of 0.1 degree (5.4 million
// rays each; 5 mm between rays 3 m away), with noise of 1 mm per metre of
// range (synth::roomScene), reconstructed with 2 threads:
//
//   BM_RoomFromTripods/<voxel mm>/0   levelfuse's MAP estimate (Reconstructor::run),
//                                     its mesh trimmed to what the scanners saw
//   BM_RoomFromTripods/<voxel mm>/1   the linear solution it starts from (VRIP-style:
//                                     the zero set of g), trimmed the same way
//   BM_Open3DRoom/<voxel mm>          Open3D 0.16's ScalableTSDFVolume (when Open3D is
//                                     found) from the same readings and origins: each
//                                     scan resampled into the six 90-degree pinhole
//                                     faces of a cube around its tripod (900 x 900
//                                     pixels, 0.1 degree at their centres), depths in
//                                     memory, sdf_trunc 4 voxels, then marching cubes
//
// The scans are made before the timed loop (the timed part starts from range
// maps in memory). Counters: seconds, cpu_seconds, peak_rss_mb (reset before
// the timed loop: run one benchmark per process), triangles, and two rulers
// against the true room:
//
//   error_rms_mm, error_mean_mm, error_p90_mm   distance of the mesh's vertices to
//                                               the true surfaces (accuracy)
//   complete_1voxel, complete_2voxels           the share of the true surfaces the
//                                               scanners saw (the noise-free readings,
//                                               every 4th ray each way) within 1 and 2
//                                               voxels of the mesh (completeness)
//
// Run with --benchmark_format=json.

#include "BenchmarkSupport.h"

#include <levelfuse/geometry/NearestTriangle.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/MeshTrim.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/SurfaceWeight.h>
#include <levelfuse/synth/Scenes.h>

#if defined(LEVELFUSE_HAVE_OPEN3D)
#include "peers/Open3DTSDF.h"
#endif

#include <tbb/global_control.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

namespace levelfuse::bench {
namespace {

using openvdb::Vec3d;

constexpr int kQuarterTurnRays = 900;   ///< 0.1 degree steps
constexpr double kNoiseAtOneMetre = 0.001;  ///< metres per metre of range
constexpr int kTruthStride = 4;         ///< every 4th noise-free ray each way measures completeness
constexpr int kCubeFace = 900;          ///< pixels across a face of the Open3D peer's cube maps

const shapes::Room kRoom;

/// The tripods' scans, with noise (`noisy`) or without, made once per process.
const std::vector<RangeMap>& roomScans(bool noisy) {
  static std::vector<RangeMap> scans[2];
  std::vector<RangeMap>& cached = scans[noisy ? 1 : 0];
  if (cached.empty()) {
    synth::SceneOptions options;
    options.resolution = kQuarterTurnRays;
    options.noise = noisy ? kNoiseAtOneMetre / kRoom.size.z() : 0.0;
    cached = synth::roomScene(kRoom, options).maps;
  }
  return cached;
}

/// Points of the true surfaces the scanners saw: their noise-free readings.
std::vector<Vec3d> seenTruth() {
  std::vector<Vec3d> points;
  for (const RangeMap& scan : roomScans(false))
    for (int v = 0; v < scan.height(); v += kTruthStride)
      for (int u = 0; u < scan.width(); u += kTruthStride)
        if (scan.valid(u, v)) points.push_back(scan.readingPoint(u, v));
  return points;
}

/// The two rulers on a mesh (xyz, three indices per triangle).
void measureAgainstTheRoom(benchmark::State& state, const std::vector<float>& xyz,
                           const std::vector<std::uint32_t>& triangles, double voxel) {
  std::vector<double> errors;
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    errors.push_back(std::fabs(kRoom(Vec3d(xyz[i], xyz[i + 1], xyz[i + 2]))));
  std::sort(errors.begin(), errors.end());
  double sum = 0.0, sumOfSquares = 0.0;
  for (double e : errors) {
    sum += e;
    sumOfSquares += e * e;
  }
  const double n = std::max<double>(1.0, static_cast<double>(errors.size()));
  state.counters["error_rms_mm"] = 1000.0 * std::sqrt(sumOfSquares / n);
  state.counters["error_mean_mm"] = 1000.0 * sum / n;
  state.counters["error_p90_mm"] = errors.empty() ? 0.0 : 1000.0 * errors[errors.size() * 9 / 10];
  const NearestTriangle nearest(xyz, triangles);
  const std::vector<Vec3d> truth = seenTruth();
  std::size_t withinOne = 0, withinTwo = 0;
  for (const Vec3d& p : truth) {
    const double d = nearest.distance(p);
    withinOne += d <= voxel;
    withinTwo += d <= 2.0 * voxel;
  }
  state.counters["complete_1voxel"] = static_cast<double>(withinOne) / static_cast<double>(truth.size());
  state.counters["complete_2voxels"] = static_cast<double>(withinTwo) / static_cast<double>(truth.size());
  state.counters["triangles"] = static_cast<double>(triangles.size() / 3);
}

/// Runs `make()` (returning xyz and triangles) in the timed loop with the
/// usual counters, then measures its mesh.
template <typename Make>
void measure(benchmark::State& state, double voxel, const Make& make) {
  roomScans(true);
  roomScans(false);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(kDefaultThreads));
  std::vector<float> xyz;
  std::vector<std::uint32_t> triangles;
  resetPeakResident();
  const double cpuStart = processCpuSeconds();
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) make(xyz, triangles);
  state.counters["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  state.counters["cpu_seconds"] = processCpuSeconds() - cpuStart;
  state.counters["peak_rss_mb"] = peakResidentMegabytes();
  measureAgainstTheRoom(state, xyz, triangles, voxel);
}

void roomFromTripods(benchmark::State& state, int millimetres, bool linear) {
  const double voxel = 0.001 * millimetres;
  measure(state, voxel, [&](std::vector<float>& xyz, std::vector<std::uint32_t>& triangles) {
    ReconstructionOptions options;
    options.voxelSize = voxel;
    const Reconstructor reconstructor(roomScans(true), options);
    ReconstructionResult result;
    if (linear) {
      result.levelSet = reconstructor.linearSolution();
      result.weight = reconstructor.surfaceWeight(*result.levelSet);
    } else {
      result = reconstructor.run();
    }
    const TriangleMesh mesh = trimMesh(meshFromLevelSet(*result.levelSet), *result.weight, kObservedWeight);
    xyz = mesh.xyz;
    triangles = mesh.triangles;
  });
}

#if defined(LEVELFUSE_HAVE_OPEN3D)
/// A face of the cube around a tripod: looking along `forward`, `down` being
/// the image's +y (OpenCV's camera frame), as rows of a row-vector matrix.
std::array<double, 16> faceToWorld(const Vec3d& forward, const Vec3d& down, const Vec3d& eye) {
  const Vec3d right = down.cross(forward);
  return {right.x(), right.y(), right.z(), 0.0, down.x(), down.y(), down.z(), 0.0,
          forward.x(), forward.y(), forward.z(), 0.0, eye.x(), eye.y(), eye.z(), 1.0};
}

/// A scan resampled into the six faces of a cube around its scanner: each
/// face pixel's ray reads the scan's range there (interpolated as the data
/// term reads it) as a depth along the face's axis.
std::vector<peers::DepthFrameImage> cubeFaces(const RangeMap& scan, const peers::DepthCamera& camera) {
  const Vec3d eye = scan.scannerPosition();
  const Vec3d axes[6][2] = {{Vec3d(1, 0, 0), Vec3d(0, 0, -1)}, {Vec3d(-1, 0, 0), Vec3d(0, 0, -1)},
                            {Vec3d(0, 1, 0), Vec3d(0, 0, -1)}, {Vec3d(0, -1, 0), Vec3d(0, 0, -1)},
                            {Vec3d(0, 0, 1), Vec3d(0, 1, 0)},  {Vec3d(0, 0, -1), Vec3d(0, 1, 0)}};
  std::vector<peers::DepthFrameImage> faces;
  for (const auto& [forward, down] : axes) {
    peers::DepthFrameImage face;
    face.cameraToWorld = faceToWorld(forward, down, eye);
    const Vec3d right = down.cross(forward);
    face.depth.assign(static_cast<std::size_t>(camera.width) * camera.height, 0.0f);
    for (int v = 0; v < camera.height; ++v)
      for (int u = 0; u < camera.width; ++u) {
        const Vec3d ray = forward + right * ((u - camera.cx) / camera.fx) + down * ((v - camera.cy) / camera.fy);
        RangeSample s;
        const Vec3d unit = ray.unit();
        if (!scan.sample(eye + unit, s)) continue;
        const double range = 1.0 - s.D;  // D = |p| - range at the point 1 m along the ray
        face.depth[static_cast<std::size_t>(v) * camera.width + u] = static_cast<float>(range * unit.dot(forward));
      }
    faces.push_back(std::move(face));
  }
  return faces;
}

void open3dRoom(benchmark::State& state, int millimetres) {
  const double voxel = 0.001 * millimetres;
  peers::DepthCamera camera;
  camera.width = camera.height = kCubeFace;
  camera.fx = camera.fy = 0.5 * kCubeFace;  // 90 degrees across
  camera.cx = camera.cy = 0.5 * (kCubeFace - 1);
  std::vector<peers::DepthFrameImage> frames;
  for (const RangeMap& scan : roomScans(true))
    for (peers::DepthFrameImage& face : cubeFaces(scan, camera)) frames.push_back(std::move(face));
  peers::TsdfSettings settings;
  settings.voxel = voxel;
  settings.truncation = 4.0 * voxel;
  settings.maxDepth = 10.0;
  measure(state, voxel, [&](std::vector<float>& xyz, std::vector<std::uint32_t>& triangles) {
    peers::PeerMesh mesh = peers::open3dTsdf(frames, camera, settings);
    xyz = std::move(mesh.xyz);
    triangles = std::move(mesh.triangles);
  });
}
#endif

void registerAll() {
  for (const int millimetres : {10, 5}) {
    const std::string suffix = "/" + std::to_string(millimetres);
#if defined(LEVELFUSE_HAVE_OPEN3D)
    benchmark::RegisterBenchmark(("BM_Open3DRoom" + suffix).c_str(), open3dRoom, millimetres)
        ->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
#endif
    for (const bool linear : {false, true})
      benchmark::RegisterBenchmark(("BM_RoomFromTripods" + suffix + (linear ? "/1" : "/0")).c_str(), roomFromTripods,
                                   millimetres, linear)
          ->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
  }
}

}  // namespace
}  // namespace levelfuse::bench

int main(int argc, char** argv) { return levelfuse::bench::runBenchmarks(argc, argv, levelfuse::bench::registerAll); }
