// End-to-end reconstruction of the Stanford bunny from its ten scans (362,272
// points): loading, the pipeline of section 6 and the surface, at 0.5 mm and
// 0.25 mm voxels, with 2 threads (and 1 for the scaling).
//
// Each benchmark reports real time per reconstruction (loading included) and
//   peak_rss_mb      the process's peak resident memory while it ran (the peak
//                    is reset before each benchmark's timed loop)
//   engine_mb        the largest sparse field along the way
//   active           voxels of the final active set
//   fit_mean_mm      mean distance from the scans' 362,272 points to the zero
//   fit_median_mm    set of the level set, its median and 90th percentile
//   fit_p90_mm
//   beyond_band      fraction of the points farther than the narrow band (holes)
//   mesh_fit_*_mm    the same distances, exact, to the triangles of its mesh
//                    (the ruler the peers are measured with)
//   rms_curvature_per_mm, median_curvature_per_mm
//                    the mesh's mean curvature where the points project onto
//                    it (measureRoughness, a 0.1 mm ruler, points within
//                    0.3 mm): how much of the scans' noise the surface keeps
//
// BM_ReconstructBunny/250/2/beta:0 is the same run without the prior (the
// roughness the target is set against). BM_HoldOutBunny/<scan>/<method> makes
// the surface from the other nine scans and measures the fit of the scan left
// out, for levelfuse and PoissonRecon: the accuracy on points the method did
// not see.
//
// The peer BM_PoissonReconBunny/<depth>/<threads> (when Open3D is found)
// times PoissonRecon from the same scans' points, normals estimated per scan
// and turned toward its scanner, and reports the fit of its mesh, and of its
// surface stored as a 0.25 mm level set (levelset_fit_mean_mm), with the same
// rulers. BM_MapFromPoissonBunny/<micrometres> then starts the finest grid's
// MAP evolution (data term and prior, as the Reconstructor runs it) from
// PoissonRecon's surface and reports the fit before and after 64 iterations
// (from_*, map_*): where the MAP estimate goes from a surface that fits the
// points more closely. Run with --benchmark_format=json; see docs/BENCHMARKS.md.

#include "BenchmarkSupport.h"

#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/DataSpeed.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/SurfaceRoughness.h>

#if defined(LEVELFUSE_HAVE_OPEN3D)
#include "peers/PoissonRecon.h"

#endif

#include <tbb/global_control.h>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <string>
#include <utility>

namespace levelfuse::bench {
namespace {

const std::string kBunny = std::string(LEVELFUSE_SHARED_DATA_DIR) + "/stanford/bunny/bun.conf";

/// The scans' original points in the world: all scans (`onlyScan` < 0) or one.
std::vector<openvdb::Vec3d> bunnyPoints(int onlyScan = -1) {
  std::vector<openvdb::Vec3d> points;
  int index = -1;
  for (const io::StanfordPlacement& p : io::readStanfordConf(kBunny)) {
    ++index;
    if (onlyScan >= 0 && index != onlyScan) continue;
    const openvdb::math::Mat4d toWorld = p.scanToWorld();
    for (const openvdb::Vec3d& q : io::readRangeGridPly(p.path).points) points.push_back(toWorld.transform(q));
  }
  return points;
}

void reportMeshFit(benchmark::State& state, const DataFit& fit) {
  state.counters["mesh_fit_mean_mm"] = 1000.0 * fit.mean;
  state.counters["mesh_fit_median_mm"] = 1000.0 * fit.median;
  state.counters["mesh_fit_p90_mm"] = 1000.0 * fit.p90;
  state.counters["mesh_fit_p99_mm"] = 1000.0 * fit.p99;
}

void reportRoughness(benchmark::State& state, const TriangleMesh& mesh, const std::vector<openvdb::Vec3d>& points) {
  const SurfaceRoughness roughness = measureRoughness(mesh, points, 0.0001, 0.0003);
  state.counters["rms_curvature_per_mm"] = roughness.rms / 1000.0;
  state.counters["median_curvature_per_mm"] = roughness.medianAbsolute / 1000.0;
}

void reconstruct(benchmark::State& state, double voxelSize, int threads, double beta) {
  if (!std::filesystem::exists(kBunny)) {
    state.SkipWithError("../shared/data/stanford/bunny is absent");
    return;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  ReconstructionResult result;
  resetPeakResident();
  for (auto _ : state) {
    result = ReconstructionResult();
    ReconstructionOptions options;
    options.voxelSize = voxelSize;
    options.beta = beta;
    result = Reconstructor(io::loadStanfordScans(kBunny), options).run();
  }
  state.counters["peak_rss_mb"] = peakResidentMegabytes();
  const std::vector<openvdb::Vec3d> points = bunnyPoints();
  const DataFit fit = measureDataFit(*result.levelSet, points);
  state.counters["engine_mb"] = static_cast<double>(result.peakEngineBytes) / 1048576.0;
  state.counters["active"] = static_cast<double>(result.levels.back().activeSetVoxels);
  state.counters["fit_mean_mm"] = 1000.0 * fit.mean;
  state.counters["fit_median_mm"] = 1000.0 * fit.median;
  state.counters["fit_p90_mm"] = 1000.0 * fit.p90;
  state.counters["beyond_band"] = fit.beyondBand;
  const TriangleMesh mesh = meshFromLevelSet(*result.levelSet);
  reportMeshFit(state, measureDataFit(mesh, points));
  reportRoughness(state, mesh, points);
  state.counters["triangles"] = static_cast<double>(mesh.triangleCount());
}

#if defined(LEVELFUSE_HAVE_OPEN3D)
/// PoissonRecon's mesh of the bunny from its scans' points, all but `leftOut` (if >= 0).
TriangleMesh poissonBunny(int depth, int threads, int leftOut = -1) {
  std::vector<peers::PoissonScan> scans;
  int index = -1;
  for (const io::StanfordPlacement& p : io::readStanfordConf(kBunny)) {
    if (++index == leftOut) continue;
    peers::PoissonScan scan;
    for (const openvdb::Vec3d& q : io::readRangeGridPly(p.path).points) scan.points.push_back({q.x(), q.y(), q.z()});
    const openvdb::math::Mat4d toWorld = p.scanToWorld();
    for (int i = 0; i < 16; ++i) scan.scanToWorld[i] = toWorld(i / 4, i % 4);
    scans.push_back(std::move(scan));
  }
  return toTriangleMesh(peers::poissonReconstruct(scans, depth, threads));
}

void poissonRecon(benchmark::State& state, int depth, int threads) {
  if (!std::filesystem::exists(kBunny)) {
    state.SkipWithError("../shared/data/stanford/bunny is absent");
    return;
  }
  TriangleMesh mesh;
  resetPeakResident();
  for (auto _ : state) mesh = poissonBunny(depth, threads);
  state.counters["peak_rss_mb"] = peakResidentMegabytes();
  const std::vector<openvdb::Vec3d> points = bunnyPoints();
  reportMeshFit(state, measureDataFit(mesh, points));
  reportRoughness(state, mesh, points);
  state.counters["triangles"] = static_cast<double>(mesh.triangleCount());
  // The same surface as a 0.25 mm OpenVDB level set, measured as levelfuse's are.
  state.counters["levelset_fit_mean_mm"] = 1000.0 * measureDataFit(*levelSetFromMesh(mesh, 0.00025), points).mean;
}

/// The surface from nine scans, measured against the tenth (2 threads, 0.25 mm).
void holdOut(benchmark::State& state, int leftOut, bool poisson) {
  if (!std::filesystem::exists(kBunny)) {
    state.SkipWithError("../shared/data/stanford/bunny is absent");
    return;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  TriangleMesh mesh;
  for (auto _ : state) {
    if (poisson) {
      mesh = poissonBunny(9, 2, leftOut);
    } else {
      std::vector<RangeMap> maps = io::loadStanfordScans(kBunny);
      maps.erase(maps.begin() + leftOut);
      ReconstructionOptions options;
      options.voxelSize = 0.00025;
      mesh = meshFromLevelSet(*Reconstructor(std::move(maps), options).run().levelSet);
    }
  }
  const std::vector<openvdb::Vec3d> points = bunnyPoints(leftOut);
  state.counters["held_out_points"] = static_cast<double>(points.size());
  reportMeshFit(state, measureDataFit(mesh, points));
}

void mapFromPoisson(benchmark::State& state, double voxelSize, double beta) {
  if (!std::filesystem::exists(kBunny)) {
    state.SkipWithError("../shared/data/stanford/bunny is absent");
    return;
  }
  ReconstructionOptions options;
  options.voxelSize = voxelSize;
  options.beta = beta;
  const Reconstructor reconstructor(io::loadStanfordScans(kBunny), options);
  const openvdb::FloatGrid::Ptr start = levelSetFromMesh(poissonBunny(9, 2), voxelSize);
  const std::vector<openvdb::Vec3d> points = bunnyPoints();
  const DataFit before = measureDataFit(*start, points);
  // The finest grid's evolution, as Reconstructor::run sets it up.
  const int finest = reconstructor.settings().levels - 1;
  const ForceField force(std::make_shared<const std::vector<RangeMap>>(reconstructor.maps()),
                         reconstructor.forceOptions(finest));
  DataSpeed<ForceField> speed;
  speed.force = DataForce<ForceField>{&force};
  speed.beta = reconstructor.settings().beta * voxelSize * voxelSize;
  speed.sampling = ForceSampling::kSubcell;
  openvdb::FloatGrid::Ptr evolved;
  for (auto _ : state) {
    SparseField field = SparseField::fromLevelSet(*start);
    for (int i = 0; i < 64; ++i) field.step(speed);
    evolved = field.toLevelSet(3.0);
  }
  const DataFit after = measureDataFit(*evolved, points);
  state.counters["beta"] = reconstructor.settings().beta;
  state.counters["from_fit_mean_mm"] = 1000.0 * before.mean;
  state.counters["from_fit_median_mm"] = 1000.0 * before.median;
  state.counters["from_fit_p90_mm"] = 1000.0 * before.p90;
  state.counters["map_fit_mean_mm"] = 1000.0 * after.mean;
  state.counters["map_fit_median_mm"] = 1000.0 * after.median;
  state.counters["map_fit_p90_mm"] = 1000.0 * after.p90;
}
#endif

void registerAll() {
  for (int micrometres : {500, 250})
    for (int threads : {2, 1})
      benchmark::RegisterBenchmark(
          ("BM_ReconstructBunny/" + std::to_string(micrometres) + "/" + std::to_string(threads)).c_str(), reconstruct,
          micrometres * 1e-6, threads, -1.0)
          ->Iterations(1)->Repetitions(3)->UseRealTime()->Unit(benchmark::kSecond);
  benchmark::RegisterBenchmark("BM_ReconstructBunny/250/2/beta:0", reconstruct, 0.00025, 2, 0.0)
      ->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
#if defined(LEVELFUSE_HAVE_OPEN3D)
  for (int threads : {2, 1})
    benchmark::RegisterBenchmark(("BM_PoissonReconBunny/9/" + std::to_string(threads)).c_str(), poissonRecon, 9, threads)
        ->Iterations(1)->Repetitions(3)->UseRealTime()->Unit(benchmark::kSecond);
  for (int scan : {0, 2, 4})
    for (const auto& [name, poisson] : {std::pair<const char*, bool>{"levelfuse", false}, {"poisson", true}})
      benchmark::RegisterBenchmark(("BM_HoldOutBunny/" + std::to_string(scan) + "/" + name).c_str(), holdOut, scan,
                                   poisson)
          ->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
  // beta: the default (-1, derived from the data) and none.
  for (const auto& [name, beta] : {std::pair<const char*, double>{"default", -1.0}, {"0", 0.0}})
    benchmark::RegisterBenchmark((std::string("BM_MapFromPoissonBunny/250/beta:") + name).c_str(), mapFromPoisson,
                                 0.00025, beta)
        ->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
#endif
}

}  // namespace
}  // namespace levelfuse::bench

int main(int argc, char** argv) { return levelfuse::bench::runBenchmarks(argc, argv, levelfuse::bench::registerAll); }
