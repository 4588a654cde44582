// Accumulation of the MAP data term (Eq. 17) from the ten Stanford bunny scans
// (362,272 points) on sparse grids of 0.5 mm and 0.25 mm voxels, with 1 and 2
// threads, and the window of defaultForceFieldOptions (eps = the voxel size:
// the scans' 0.2 mm sigma is less), as the Reconstructor uses it.
//
// Each benchmark reports real time per accumulation and the counters
//   points_per_second  scan points integrated per second (vdbfusion, single-
//                      threaded TSDF integration on OpenVDB, manages about
//                      2.4 M/s on the bunny at 0.5 mm on the reference machine)
//   evaluations        (voxel, range map) pairs evaluated
//   voxels             voxels some window reaches (the sparse grid's active voxels)
//   grid_mb            memory of the accumulated g and weight grids
//   peak_rss_mb        the process's peak resident memory so far (run one
//                      benchmark per process for its own peak; see docs)
// Run with --benchmark_format=json; see docs/BENCHMARKS.md.

#include "BenchmarkSupport.h"

#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/scan/ForceField.h>

#include <tbb/global_control.h>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <string>

namespace levelfuse::bench {
namespace {

constexpr std::size_t kBunnyPoints = 362272;

const std::vector<RangeMap>* bunny() {
  static const std::unique_ptr<std::vector<RangeMap>> maps = [] {
    const std::string conf = std::string(LEVELFUSE_SHARED_DATA_DIR) + "/stanford/bunny/bun.conf";
    if (!std::filesystem::exists(conf)) return std::unique_ptr<std::vector<RangeMap>>();
    return std::make_unique<std::vector<RangeMap>>(io::loadStanfordScans(conf));
  }();
  return maps.get();
}

void accumulate(benchmark::State& state, double voxelSize, int threads) {
  const std::vector<RangeMap>* maps = bunny();
  if (!maps) {
    state.SkipWithError("../shared/data/stanford/bunny is absent");
    return;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  const ForceField field(*maps, defaultForceFieldOptions(*maps, voxelSize));
  AccumulatedField result;
  for (auto _ : state) {
    result = AccumulatedField();  // the previous grids go before the next are built
    result = field.accumulate(voxelSize);
  }
  state.counters["points_per_second"] =
      benchmark::Counter(static_cast<double>(kBunnyPoints), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["evaluations"] = static_cast<double>(result.evaluations);
  state.counters["voxels"] = static_cast<double>(result.g->activeVoxelCount());
  state.counters["grid_mb"] = static_cast<double>(result.g->memUsage() + result.weight->memUsage()) / 1e6;
  state.counters["peak_rss_mb"] = peakResidentMegabytes();
}

void registerAll() {
  for (int micrometres : {500, 250})
    for (int threads : {1, 2})
      benchmark::RegisterBenchmark(
          ("BM_ForceFieldAccumulate/" + std::to_string(micrometres) + "/" + std::to_string(threads)).c_str(),
          accumulate, micrometres * 1e-6, threads)
          ->Repetitions(3)->UseRealTime()->Unit(benchmark::kMillisecond);
}

}  // namespace
}  // namespace levelfuse::bench

int main(int argc, char** argv) { return levelfuse::bench::runBenchmarks(argc, argv, levelfuse::bench::registerAll); }
