// End-to-end reconstruction of the Stanford bunny from its ten scans (362,272
// points): loading, the pipeline of section 6 and the surface, at 0.5 mm and
// 0.25 mm voxels, with 2 threads (and 1 for the scaling).
//
// Each benchmark reports real time per reconstruction (loading included) and
//   peak_rss_mb      the process's peak resident memory (run one benchmark per
//                    process for its own peak: --benchmark_filter)
//   engine_mb        the largest sparse field along the way
//   active           voxels of the final active set
//   fit_mean_mm      mean distance from the scans' 362,272 points to the zero
//   fit_median_mm    set of the level set, its median and 90th percentile
//   fit_p90_mm
//   beyond_band      fraction of the points farther than the narrow band (holes)
//   mesh_fit_*_mm    the same distances, exact, to the triangles of its mesh
//                    (the ruler the peers are measured with)
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

#include <levelfuse/io/StanfordScans.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/DataSpeed.h>
#include <levelfuse/recon/Reconstructor.h>

#if defined(LEVELFUSE_HAVE_OPEN3D)
#include "peers/PoissonRecon.h"

#include <openvdb/tools/MeshToVolume.h>
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

/// The scans' original points in the world.
std::vector<openvdb::Vec3d> bunnyPoints() {
  std::vector<openvdb::Vec3d> points;
  for (const io::StanfordPlacement& p : io::readStanfordConf(kBunny)) {
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

void reconstruct(benchmark::State& state, double voxelSize, int threads) {
  if (!std::filesystem::exists(kBunny)) {
    state.SkipWithError("../shared/data/stanford/bunny is absent");
    return;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  ReconstructionResult result;
  for (auto _ : state) {
    result = ReconstructionResult();
    ReconstructionOptions options;
    options.voxelSize = voxelSize;
    result = Reconstructor(io::loadStanfordScans(kBunny), options).run();
  }
  state.counters["peak_rss_mb"] = peakResidentMegabytes();
  const std::vector<openvdb::Vec3d> points = bunnyPoints();
  const DataFit fit = measureDataFit(*result.levelSet, points);
  state.counters["engine_mb"] = static_cast<double>(result.peakEngineBytes) / 1048576.0;
  state.counters["active"] = static_cast<double>(result.levels.back().activeVoxels);
  state.counters["fit_mean_mm"] = 1000.0 * fit.mean;
  state.counters["fit_median_mm"] = 1000.0 * fit.median;
  state.counters["fit_p90_mm"] = 1000.0 * fit.p90;
  state.counters["beyond_band"] = fit.beyondBand;
  const TriangleMesh mesh = meshFromLevelSet(*result.levelSet);
  reportMeshFit(state, measureDataFit(mesh, points));
  state.counters["triangles"] = static_cast<double>(mesh.triangleCount());
}

#if defined(LEVELFUSE_HAVE_OPEN3D)
/// PoissonRecon's mesh of the bunny from its scans' points.
TriangleMesh poissonBunny(int depth, int threads) {
  std::vector<peers::PoissonScan> scans;
  for (const io::StanfordPlacement& p : io::readStanfordConf(kBunny)) {
    peers::PoissonScan scan;
    for (const openvdb::Vec3d& q : io::readRangeGridPly(p.path).points) scan.points.push_back({q.x(), q.y(), q.z()});
    const openvdb::math::Mat4d toWorld = p.scanToWorld();
    for (int i = 0; i < 16; ++i) scan.scanToWorld[i] = toWorld(i / 4, i % 4);
    scans.push_back(std::move(scan));
  }
  peers::PoissonMesh result = peers::poissonReconstruct(scans, depth, threads);
  TriangleMesh mesh;
  mesh.xyz = std::move(result.xyz);
  mesh.triangles = std::move(result.triangles);
  return mesh;
}

/// A mesh as an OpenVDB level set of `voxelSize` (half-width 3).
openvdb::FloatGrid::Ptr levelSetOf(const TriangleMesh& mesh, double voxelSize) {
  const auto transform = openvdb::math::Transform::createLinearTransform(voxelSize);
  std::vector<openvdb::Vec3s> vertices(mesh.vertexCount());
  for (std::size_t i = 0; i < vertices.size(); ++i)
    vertices[i] = openvdb::Vec3s(mesh.xyz[3 * i], mesh.xyz[3 * i + 1], mesh.xyz[3 * i + 2]);
  std::vector<openvdb::Vec3I> triangles(mesh.triangleCount());
  for (std::size_t i = 0; i < triangles.size(); ++i)
    triangles[i] = openvdb::Vec3I(mesh.triangles[3 * i], mesh.triangles[3 * i + 1], mesh.triangles[3 * i + 2]);
  return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, vertices, triangles, 3.0f);
}

void poissonRecon(benchmark::State& state, int depth, int threads) {
  if (!std::filesystem::exists(kBunny)) {
    state.SkipWithError("../shared/data/stanford/bunny is absent");
    return;
  }
  TriangleMesh mesh;
  for (auto _ : state) mesh = poissonBunny(depth, threads);
  state.counters["peak_rss_mb"] = peakResidentMegabytes();
  const std::vector<openvdb::Vec3d> points = bunnyPoints();
  reportMeshFit(state, measureDataFit(mesh, points));
  state.counters["triangles"] = static_cast<double>(mesh.triangleCount());
  // The same surface as a 0.25 mm OpenVDB level set, measured as levelfuse's are.
  state.counters["levelset_fit_mean_mm"] = 1000.0 * measureDataFit(*levelSetOf(mesh, 0.00025), points).mean;
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
  const openvdb::FloatGrid::Ptr start = levelSetOf(poissonBunny(9, 2), voxelSize);
  const std::vector<openvdb::Vec3d> points = bunnyPoints();
  const DataFit before = measureDataFit(*start, points);
  // The finest grid's evolution, as Reconstructor::run sets it up.
  const int finest = reconstructor.options().levels - 1;
  const ForceField force(std::make_shared<const std::vector<RangeMap>>(reconstructor.maps()),
                         reconstructor.forceOptions(finest));
  DataSpeed speed;
  speed.force = DataForce{&force, force.typicalWeight()};
  speed.beta = reconstructor.options().beta * voxelSize * voxelSize;
  speed.sampling = ForceSampling::kSubcell;
  openvdb::FloatGrid::Ptr evolved;
  for (auto _ : state) {
    SparseField field = SparseField::fromLevelSet(*start);
    for (int i = 0; i < 64; ++i) field.step(speed);
    evolved = field.toLevelSet(3.0);
  }
  const DataFit after = measureDataFit(*evolved, points);
  state.counters["beta"] = reconstructor.options().beta;
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
          micrometres * 1e-6, threads)
          ->Iterations(1)->Repetitions(3)->UseRealTime()->Unit(benchmark::kSecond);
#if defined(LEVELFUSE_HAVE_OPEN3D)
  for (int threads : {2, 1})
    benchmark::RegisterBenchmark(("BM_PoissonReconBunny/9/" + std::to_string(threads)).c_str(), poissonRecon, 9, threads)
        ->Iterations(1)->Repetitions(3)->UseRealTime()->Unit(benchmark::kSecond);
  // beta: the default (-1, derived from the data) and none.
  for (const auto& [name, beta] : {std::pair<const char*, double>{"default", -1.0}, {"0", 0.0}})
    benchmark::RegisterBenchmark((std::string("BM_MapFromPoissonBunny/250/beta:") + name).c_str(), mapFromPoisson,
                                 0.00025, beta)
        ->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
#endif
}

}  // namespace
}  // namespace levelfuse::bench

int main(int argc, char** argv) {
  openvdb::initialize();
  levelfuse::bench::registerAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
