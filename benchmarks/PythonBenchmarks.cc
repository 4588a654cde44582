// The Python module's overhead: the Stanford bunny reconstructed from its ten
// scans through `levelfuse.reconstruct` in an embedded interpreter, beside the
// same work from C++ (the library calls the module makes: the scans read and
// held packed, the reconstruction, its weight grid and the fit the summary
// reports), in the same program and run, 2 threads.
//
//   BM_BunnyFromCpp/<voxel um>     the C++ path
//   BM_BunnyFromPython/<voxel um>  levelfuse.reconstruct(path, voxel_size=...)
//
// Each reports real time per reconstruction (loading included) and
//   cpu_seconds   the process's CPU time per reconstruction, all threads
//   active        voxels of the final narrow band (the two paths agree)
// The overhead is the ratio of the two times (docs/BENCHMARKS.md). Repetitions
// (--benchmark_repetitions) give the spread on a shared machine.

#include "BenchmarkSupport.h"

#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/ScansReconstruction.h>

#include <benchmark/benchmark.h>
#include <pybind11/embed.h>
#include <tbb/global_control.h>

#include <filesystem>
#include <string>

namespace levelfuse::bench {
namespace {

namespace py = pybind11;

const std::string kBunny = std::string(LEVELFUSE_SHARED_DATA_DIR) + "/stanford/bunny/bun.conf";

double voxelOf(const benchmark::State& state) { return 1e-6 * static_cast<double>(state.range(0)); }

/// What levelfuse.reconstruct does, from C++: the narrow band's voxels.
std::size_t reconstructFromCpp(double voxelSize) {
  PackedScans scans;
  io::ScanLoadOptions load;
  load.take = [&](RangeMap&& map) { scans.add(std::move(map)); };
  io::loadScans(kBunny, load);
  ReconstructionOptions options;
  options.voxelSize = voxelSize;
  const ReconstructionSettings settings = resolveReconstructionSettings(options, scans.summary);
  ScansReconstruction r = prepareReconstruction(std::move(scans), settings);
  ReconstructionResult result = r.reconstructor->run();
  describeInputs(*result.levelSet, {kBunny}, false, r.reconstructor->summary().aScene());
  r.letTheGridsGo();
  const DataFit fit = measureDataFit(*result.levelSet, r.scans, fitStride(r.scans, kFitPointsAtMost));
  benchmark::DoNotOptimize(fit.mean);
  return result.levelSet->activeVoxelCount();
}

void report(benchmark::State& state, double cpuSeconds, std::size_t active) {
  state.counters["cpu_seconds"] = cpuSeconds / static_cast<double>(state.iterations());
  state.counters["active"] = static_cast<double>(active);
}

void BM_BunnyFromCpp(benchmark::State& state) {
  if (!std::filesystem::exists(kBunny)) return state.SkipWithError("the Stanford bunny is not in ../shared/data");
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, kDefaultThreads);
  std::size_t active = 0;
  const double cpu = processCpuSeconds();
  for (auto _ : state) active = reconstructFromCpp(voxelOf(state));
  report(state, processCpuSeconds() - cpu, active);
}

void BM_BunnyFromPython(benchmark::State& state) {
  if (!std::filesystem::exists(kBunny)) return state.SkipWithError("the Stanford bunny is not in ../shared/data");
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, kDefaultThreads);
  py::module_::import("sys").attr("path").attr("insert")(0, LEVELFUSE_PYTHON_DIR);
  const py::object reconstruct = py::module_::import("levelfuse").attr("reconstruct");
  std::size_t active = 0;
  const double cpu = processCpuSeconds();
  for (auto _ : state) {
    const py::object result = reconstruct(kBunny, py::arg("voxel_size") = voxelOf(state));
    active = result.attr("summary")["narrow_band_voxels"].cast<std::size_t>();
  }
  report(state, processCpuSeconds() - cpu, active);
}

void registerAll() {
  for (int micrometres : {500, 250}) {
    benchmark::RegisterBenchmark("BM_BunnyFromCpp", BM_BunnyFromCpp)
        ->Arg(micrometres)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
    benchmark::RegisterBenchmark("BM_BunnyFromPython", BM_BunnyFromPython)
        ->Arg(micrometres)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
  }
}

}  // namespace
}  // namespace levelfuse::bench

int main(int argc, char** argv) {
  const pybind11::scoped_interpreter python;
  return levelfuse::bench::runBenchmarks(argc, argv, levelfuse::bench::registerAll);
}
