// Depth video: the 7-Scenes sequence in ../shared/data/7scenes-seq (500
// frames, every second frame of the recording, 640x480 Kinect depth in
// millimetres), fused at 10 mm and 5 mm voxels from 50 frames (every 10th:
// positions 0, 10, ..., 490) and from all 500, with 2 threads.
//
//   BM_FuseDepthFrames/<voxel mm>/<frames>   levelfuse end to end, frames on disk
//                                            to mesh: io::loadScans, Reconstructor::run
//                                            (the MAP estimate), meshFromLevelSet
//   BM_LinearDepthFrames/<voxel mm>/<frames> the same with Reconstructor::linearSolution
//                                            (the zero set of g, Eq. 17) for the surface
//   BM_Open3DTSDF/<voxel mm>/<frames>        Open3D 0.16's ScalableTSDFVolume (when
//                                            Open3D is found): its own PNG reader,
//                                            sdf_trunc 4 voxels, depth_trunc 4 m, no
//                                            colour, integrate + extract_triangle_mesh
//
//   BM_FuseOneFrame/<voxel mm>               live fusion: Fusion::integrate of one frame
//                                            (decoded beforehand) into a fusion of one
//                                            grid, over the sequence's first 100 frames;
//                                            counters ms_per_frame_median, _p90, _max,
//                                            evaluations_per_frame, readings_per_frame
//   BM_AnswerAfterFrames/<voxel mm>/<frames> the answer a scanning app shows while frames
//                                            keep coming: Fusion::linearSolution after
//                                            the first <frames> frames (carving from
//                                            scratch: the first answer)
//   BM_AnswerEveryFrames/<voxel mm>/<frames>/<every>  the same answer after every <every>
//                                            frames of the first <frames>, as an app
//                                            refreshes its view (carving's votes kept
//                                            from the last answer); counters
//                                            answer_ms_median, answer_ms_max, answers
//
// Counters: seconds (the timed loop, as the real time), cpu_seconds (the CPU
// time of all the process's threads in it: a measure that holds on a shared
// machine, where the real time is not the run's own), peak_rss_mb (the
// process's peak resident memory, reset before the timed loop: run one
// benchmark per process, as tools/quickstart.sh bench does), triangles, and
// the accuracy of the mesh on held-out frames (measureHeldOutFrames):
//
//   held-out frames  the 50 at positions 5, 15, ..., 495 of the sequence
//                    (frame-000010, frame-000030, ..., frame-000990), every 2nd
//                    pixel in each direction (about 3.4 million points);
//                    the 50-frame runs never see them.
//   heldout_mean_mm, heldout_median_mm, heldout_p90_mm, heldout_within_1cm,
//   heldout_within_2cm, heldout_within_5cm, heldout_points
//
// The 500-frame runs use every frame, the held-out ones included: there the
// same ruler measures how well the surface fits frames it was built from, and
// its counters are named seen_* instead of heldout_*.
//
// Open3D runs its loops with OpenMP in the environment it is given, as its
// users run it; levelfuse runs on 2 TBB threads. The whole-process comparison
// with Open3D's Python API is benchmarks/depth_video_processes.py.
//
// Run with --benchmark_format=json; skipped with a message without the data.

#include "BenchmarkSupport.h"
#include "DepthSequence.h"

#include <levelfuse/core/FreedMemory.h>
#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/recon/Fusion.h>
#include <levelfuse/recon/HeldOutFrames.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/ScansReconstruction.h>
#include <levelfuse/scan/PackedRangeMap.h>

#if defined(LEVELFUSE_HAVE_OPEN3D)
#include "peers/Open3DTSDF.h"
#endif

#include <tbb/global_control.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace levelfuse::bench {
namespace {

namespace fs = std::filesystem;

const std::string kSequence = std::string(LEVELFUSE_SHARED_DATA_DIR) + "/7scenes-seq";
constexpr std::size_t kSequenceFrames = 500;
constexpr int kHeldOutEvery = 10, kHeldOutOffset = 5;  ///< positions 5, 15, ..., 495
constexpr int kHeldOutPixelStride = 2;

/// Every `stride`-th frame from the first, as loadScans' frame stride takes them.
int strideFor(int frames) { return static_cast<int>(kSequenceFrames) / frames; }

/// True if the frames built from include some of the held-out ones.
bool seesHeldOutFrames(int frames) {
  for (const std::size_t i : splitFrames(kSequenceFrames, kHeldOutEvery, kHeldOutOffset).heldOut)
    if (i % static_cast<std::size_t>(strideFor(frames)) == 0) return true;
  return false;
}

bool sequencePresent(benchmark::State& state) {
  if (fs::exists(kSequence) && frameStems(kSequence).size() == kSequenceFrames) return true;
  state.SkipWithError("../shared/data/7scenes-seq (500 depth frames) is absent");
  return false;
}

/// levelfuse from frames on disk to a mesh, as the converter goes: the frames
/// read one at a time and held packed, the settings derived from their
/// summary, the frames fused into the grids (prepareReconstruction, as the
/// converter and the Python module do), then the MAP estimate or the
/// linear solution it starts from. One function, so that a faster engine can
/// take its place.
TriangleMesh fuseDepthFrames(int frameStride, double voxel, bool linearOnly) {
  PackedScans frames;
  io::ScanLoadOptions load;
  load.frameStride = frameStride;
  load.take = [&](RangeMap&& frame) { frames.add(std::move(frame)); };
  io::loadScans(kSequence, load);
  ReconstructionOptions options;
  options.voxelSize = voxel;
  const ReconstructionSettings settings = resolveReconstructionSettings(options, frames.summary);
  openvdb::FloatGrid::Ptr surface;
  {
    const ScansReconstruction r = prepareReconstruction(std::move(frames), settings);
    surface = linearOnly ? r.reconstructor->linearSolution() : r.reconstructor->run().levelSet;
  }  // the grids and the frames are let go before meshing, as the converter does
  returnFreedMemory();
  return meshFromLevelSet(*surface);
}

/// Time, memory and accuracy of the mesh `make()` returns.
template <typename Make>
void measure(benchmark::State& state, int frames, const Make& make) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(kDefaultThreads));
  TriangleMesh mesh;
  resetPeakResident();
  const double cpuStart = processCpuSeconds();
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) mesh = make();
  state.counters["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  state.counters["cpu_seconds"] = processCpuSeconds() - cpuStart;
  state.counters["peak_rss_mb"] = peakResidentMegabytes();
  state.counters["frames"] = frames;
  state.counters["triangles"] = static_cast<double>(mesh.triangleCount());
  HeldOutOptions options;
  options.stride = kHeldOutPixelStride;
  const HeldOutAccuracy accuracy =
      measureHeldOutFrames(mesh, heldOutFrames(kSequence, kHeldOutEvery, kHeldOutOffset), options);
  const std::string prefix = seesHeldOutFrames(frames) ? "seen_" : "heldout_";
  state.counters[prefix + "points"] = static_cast<double>(accuracy.distances.readings);
  state.counters[prefix + "mean_mm"] = 1000.0 * accuracy.distances.mean;
  state.counters[prefix + "median_mm"] = 1000.0 * accuracy.distances.median;
  state.counters[prefix + "p90_mm"] = 1000.0 * accuracy.distances.p90;
  state.counters[prefix + "within_1cm"] = accuracy.within[0];
  state.counters[prefix + "within_2cm"] = accuracy.within[1];
  state.counters[prefix + "within_5cm"] = accuracy.within[2];
}

void levelfuseDepth(benchmark::State& state, int voxelMillimetres, int frames, bool linearOnly) {
  if (!sequencePresent(state)) return;
  measure(state, frames, [&] { return fuseDepthFrames(strideFor(frames), 0.001 * voxelMillimetres, linearOnly); });
}

#if defined(LEVELFUSE_HAVE_OPEN3D)
/// Open3D from frames on disk to a mesh: the poses and intrinsics read with
/// levelfuse's readers (plain text), the PNGs with Open3D's.
TriangleMesh open3dDepthFrames(int frameStride, double voxel) {
  const std::vector<std::string> stems = frameStems(kSequence);
  std::vector<peers::DepthFrameFile> files;
  for (std::size_t i = 0; i < stems.size(); i += static_cast<std::size_t>(frameStride)) {
    peers::DepthFrameFile file;
    file.depthPng = stems[i] + ".depth.png";
    const openvdb::math::Mat4d pose = io::readPose(stems[i] + ".pose.txt");
    for (int k = 0; k < 16; ++k) file.cameraToWorld[k] = pose(k / 4, k % 4);
    files.push_back(file);
  }
  const PinholeProjection p = io::readIntrinsics(kSequence + "/camera-intrinsics.txt");
  peers::DepthCamera camera;
  camera.fx = p.fx;
  camera.fy = p.fy;
  camera.cx = p.cx;
  camera.cy = p.cy;
  peers::TsdfSettings settings;
  settings.voxel = voxel;
  settings.truncation = 4.0 * voxel;
  return toTriangleMesh(peers::open3dTsdf(files, camera, settings));
}

void open3dDepth(benchmark::State& state, int voxelMillimetres, int frames) {
  if (!sequencePresent(state)) return;
  measure(state, frames, [&] { return open3dDepthFrames(strideFor(frames), 0.001 * voxelMillimetres); });
}
#endif

/// The sequence's first `count` frames, decoded as the Python module's users hold them.
std::vector<RangeMap> firstFrames(std::size_t count) {
  const std::vector<std::string> stems = frameStems(kSequence);
  const PinholeProjection intrinsics = io::readIntrinsics(kSequence + "/camera-intrinsics.txt");
  std::vector<RangeMap> frames;
  for (std::size_t i = 0; i < count && i < stems.size(); ++i)
    frames.push_back(io::depthFrame(io::readDepthPng(stems[i] + ".depth.png"), intrinsics,
                                    io::readPose(stems[i] + ".pose.txt"), io::DepthNoise(), stems[i]));
  return frames;
}

/// A fusion as the Python module makes one by default (epsilon one voxel).
FusionSettings liveSettings(int voxelMillimetres) {
  FusionSettings settings;
  settings.voxelSize = 0.001 * voxelMillimetres;
  settings.epsilon = settings.voxelSize;
  return settings;
}

/// Fusion::integrate of each of the first 100 frames, one at a time, timed each.
void fuseOneFrame(benchmark::State& state, int voxelMillimetres) {
  if (!sequencePresent(state)) return;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(kDefaultThreads));
  const std::vector<RangeMap> frames = firstFrames(100);
  std::vector<double> milliseconds;
  std::size_t evaluations = 0;
  for (auto _ : state) {
    Fusion fusion(liveSettings(voxelMillimetres));
    for (const RangeMap& frame : frames) {
      const auto start = std::chrono::steady_clock::now();
      fusion.integrate(frame);
      milliseconds.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    evaluations = fusion.dataTerm(0).evaluations();
  }
  std::sort(milliseconds.begin(), milliseconds.end());
  std::size_t readings = 0;
  for (const RangeMap& frame : frames) readings += frame.validCount();
  // The work of a frame: (voxel, frame) pairs evaluated, and readings.
  state.counters["evaluations_per_frame"] = static_cast<double>(evaluations) / static_cast<double>(frames.size());
  state.counters["readings_per_frame"] = static_cast<double>(readings) / static_cast<double>(frames.size());
  state.counters["frames"] = static_cast<double>(milliseconds.size());
  state.counters["ms_per_frame_median"] = milliseconds[milliseconds.size() / 2];
  state.counters["ms_per_frame_p90"] = milliseconds[milliseconds.size() * 9 / 10];
  state.counters["ms_per_frame_max"] = milliseconds.back();
}

/// Fusion::linearSolution after the first `count` frames: what an app shows as the room grows.
void answerAfterFrames(benchmark::State& state, int voxelMillimetres, int count) {
  if (!sequencePresent(state)) return;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(kDefaultThreads));
  Fusion fusion(liveSettings(voxelMillimetres));
  for (const RangeMap& frame : firstFrames(static_cast<std::size_t>(count))) fusion.integrate(frame);
  openvdb::FloatGrid::Ptr surface;
  for (auto _ : state) surface = fusion.linearSolution();
  state.counters["active_voxels"] = static_cast<double>(surface->activeVoxelCount());
}

void answerEveryFrames(benchmark::State& state, int voxelMillimetres, int count, int every) {
  if (!sequencePresent(state)) return;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(kDefaultThreads));
  const std::vector<RangeMap> frames = firstFrames(static_cast<std::size_t>(count));
  std::vector<double> milliseconds;
  for (auto _ : state) {
    Fusion fusion(liveSettings(voxelMillimetres));
    for (std::size_t i = 0; i < frames.size(); ++i) {
      state.PauseTiming();
      fusion.integrate(frames[i]);
      state.ResumeTiming();
      if ((i + 1) % static_cast<std::size_t>(every) != 0) continue;
      const auto start = std::chrono::steady_clock::now();
      benchmark::DoNotOptimize(fusion.linearSolution());
      milliseconds.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
  }
  std::sort(milliseconds.begin(), milliseconds.end());
  state.counters["answers"] = static_cast<double>(milliseconds.size());
  state.counters["answer_ms_median"] = milliseconds[milliseconds.size() / 2];
  state.counters["answer_ms_max"] = milliseconds.back();
}

void registerAll() {
  benchmark::RegisterBenchmark("BM_FuseOneFrame/10", fuseOneFrame, 10)->Iterations(1)->UseRealTime()->Unit(
      benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_AnswerAfterFrames/10/100", answerAfterFrames, 10, 100)
      ->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_AnswerEveryFrames/10/100/10", answerEveryFrames, 10, 100, 10)
      ->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);
  for (const int millimetres : {10, 5})
    for (const int frames : {50, 500}) {
      const std::string suffix = "/" + std::to_string(millimetres) + "/" + std::to_string(frames);
#if defined(LEVELFUSE_HAVE_OPEN3D)
      benchmark::RegisterBenchmark(("BM_Open3DTSDF" + suffix).c_str(), open3dDepth, millimetres, frames)
          ->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
#endif
      benchmark::RegisterBenchmark(("BM_FuseDepthFrames" + suffix).c_str(), levelfuseDepth, millimetres, frames, false)
          ->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
      benchmark::RegisterBenchmark(("BM_LinearDepthFrames" + suffix).c_str(), levelfuseDepth, millimetres, frames,
                                   true)
          ->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
    }
}

}  // namespace
}  // namespace levelfuse::bench

int main(int argc, char** argv) { return levelfuse::bench::runBenchmarks(argc, argv, levelfuse::bench::registerAll); }
