// End-to-end reconstruction of the Stanford bunny from its ten scans (362,272
// points): loading, the pipeline of section 6 and the surface, at 0.5 mm and
// 0.25 mm voxels, with 2 threads (and 1 for the scaling).
//
// Each benchmark reports real time per reconstruction (loading included) and
//   peak_rss_mb      the process's peak resident memory (run one benchmark per
//                    process for its own peak: --benchmark_filter)
//   engine_mb        the largest sparse field along the way
//   active           voxels of the final active set
//   fit_mean_mm      mean distance from the scans' 362,272 points to the surface
//   fit_median_mm    and its median
//   beyond_band      fraction of the points farther than the narrow band (holes)
// Run with --benchmark_format=json; see docs/BENCHMARKS.md.

#include "BenchmarkSupport.h"

#include <levelfuse/io/StanfordScans.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/Reconstructor.h>

#include <tbb/global_control.h>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

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
  const DataFit fit = measureDataFit(*result.levelSet, bunnyPoints());
  state.counters["peak_rss_mb"] = peakResidentMegabytes();
  state.counters["engine_mb"] = static_cast<double>(result.peakEngineBytes) / 1048576.0;
  state.counters["active"] = static_cast<double>(result.levels.back().activeVoxels);
  state.counters["fit_mean_mm"] = 1000.0 * fit.mean;
  state.counters["fit_median_mm"] = 1000.0 * fit.median;
  state.counters["beyond_band"] = fit.beyondBand;
}

void registerAll() {
  for (int micrometres : {500, 250})
    for (int threads : {2, 1})
      benchmark::RegisterBenchmark(
          ("BM_ReconstructBunny/" + std::to_string(micrometres) + "/" + std::to_string(threads)).c_str(), reconstruct,
          micrometres * 1e-6, threads)
          ->Iterations(1)->Repetitions(3)->UseRealTime()->Unit(benchmark::kSecond);
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
