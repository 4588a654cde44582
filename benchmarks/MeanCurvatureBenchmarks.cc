// Mean-curvature flow of a sphere of radius R voxels: levelfuse's sparse field,
// its dense-field reference, and two peers (ITK's parallel sparse field and
// OpenVDB's LevelSetFilter) in the same program, on the same machine.
//
// Every benchmark reports real time per iteration and the counters
//   active           voxels of the active set (|phi| <= 1/2 voxel for OpenVDB)
//   bytes_per_voxel  the method's memory over the voxels of its layers
//   sim_time         simulated time advanced per iteration, measured from the
//                    shape and normalised so that R(t)^2 = R0^2 - 4t for every
//                    library (OpenVDB's meanCurvature moves at half the sum of
//                    principal curvatures, ITK and levelfuse at the sum)
//   sec_per_sim_time wall seconds per unit of simulated time: cost per progress
// Run with --benchmark_format=json; see docs/BENCHMARKS.md.

#include "BenchmarkSupport.h"

#include <levelfuse/levelset/DenseField.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>

#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <tbb/global_control.h>

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>

#if defined(LEVELFUSE_HAVE_ITK)
#include "peers/ItkSparseField.h"
#endif

namespace levelfuse::bench {
namespace {

using Clock = std::chrono::steady_clock;

// Off the grid's symmetry, so no special alignment flatters anyone.
openvdb::Vec3d centreFor(int radius) { return openvdb::Vec3d(0.31, -0.17, 0.42) + openvdb::Vec3d(radius % 3); }

openvdb::FloatGrid::Ptr sphere(int radius) {
  return openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(static_cast<float>(radius),
                                                                   openvdb::Vec3f(centreFor(radius)), 1.0f, 3.0f);
}

void report(benchmark::State& state, double r0, double r1, double seconds, std::size_t active, double bytesPerVoxel) {
  const std::size_t iterations = static_cast<std::size_t>(state.iterations());
  const double simTime = simulatedTimePerIteration(r0, r1, iterations);
  state.counters["active"] = static_cast<double>(active);
  state.counters["bytes_per_voxel"] = bytesPerVoxel;
  state.counters["sim_time"] = simTime;
  state.counters["sec_per_sim_time"] = simTime > 0.0 ? seconds / (simTime * static_cast<double>(iterations)) : 0.0;
}

void sparseField(benchmark::State& state, int radius, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  SparseField field = SparseField::fromLevelSet(*sphere(radius));
  const MeanCurvatureFlow flow{1.0};
  for (int i = 0; i < 5; ++i) field.step(flow);  // warm-up
  const openvdb::Vec3d centre = centreFor(radius);
  const double r0 = meanRadius(field.grid(), centre);
  const auto start = Clock::now();
  for (auto _ : state) field.step(flow);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const SparseFieldStats stats = field.stats();
  report(state, r0, meanRadius(field.grid(), centre), seconds, stats.activeSetVoxels,
         double(stats.memoryBytes) / double(stats.bandVoxels));
}

void denseField(benchmark::State& state, int radius, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  const openvdb::Vec3d centre = centreFor(radius);
  const int half = radius + 6;
  const openvdb::Coord c = openvdb::Coord::round(centre);
  DenseField field(openvdb::CoordBBox(c - openvdb::Coord(half), c + openvdb::Coord(half)),
                   openvdb::math::Transform::createLinearTransform(1.0),
                   [&](const openvdb::Vec3d& p) { return (p - centre).length() - radius; });
  const MeanCurvatureFlow flow{1.0};
  const double r0 = meanRadius(*field.toGrid(), centre);
  std::size_t active = 0;
  const auto start = Clock::now();
  for (auto _ : state) active = field.step(flow).activeSetVoxels;
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double voxels = static_cast<double>(field.box().volume());
  report(state, r0, meanRadius(*field.toGrid(), centre), seconds, active, double(field.memoryBytes()) / voxels);
}

void openvdbFilter(benchmark::State& state, int radius, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  openvdb::FloatGrid::Ptr grid = sphere(radius);
  openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*grid);
  const openvdb::Vec3d centre = centreFor(radius);
  filter.meanCurvature();  // warm-up
  const double r0 = meanRadius(*grid, centre);
  const auto start = Clock::now();
  for (auto _ : state) filter.meanCurvature();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::size_t active = 0;
  const float half = 0.5f;
  for (auto it = grid->cbeginValueOn(); it; ++it)
    if (std::fabs(*it) <= half) ++active;
  report(state, r0, meanRadius(*grid, centre), seconds, active,
         double(grid->memUsage()) / double(grid->activeVoxelCount()));
}

#if defined(LEVELFUSE_HAVE_ITK)
void itkSparseField(benchmark::State& state, int radius, int threads) {
  peers::itkConfigureThreading(threads);
  peers::ItkSparseField field(radius, threads, 2);
  field.step(10);  // initialisation and a fixed warm-up: ITK slows as its lists age
  const double r0 = field.meanRadius();
  // Each timed iteration runs 10 ITK iterations in one Update() and reports the
  // in-loop time of one, which leaves out ITK's per-Update() full-image pass.
  double seconds = 0.0;
  for (auto _ : state) {
    field.step(10);
    const double perIteration = field.lastStepSecondsPerIteration();
    state.SetIterationTime(perIteration);
    seconds += perIteration;
  }
  const double r1 = field.meanRadius();
  // sim_time per reported iteration is per ITK iteration: ten ran per report.
  const double simTime = simulatedTimePerIteration(r0, r1, 10 * static_cast<std::size_t>(state.iterations()));
  state.counters["active"] = static_cast<double>(field.activeSetVoxels());
  state.counters["bytes_per_voxel"] = double(field.imageBytes()) / double(field.layerNodes());
  state.counters["sim_time"] = simTime;
  state.counters["sec_per_sim_time"] = simTime > 0.0 ? seconds / (simTime * double(state.iterations())) : 0.0;
}
#endif

constexpr int kRadii[] = {25, 50, 100, 200};

void registerAll() {
  for (int r : kRadii) {
    const auto iterations = static_cast<benchmark::IterationCount>(iterationsFor(r));
    const std::string R = "/" + std::to_string(r);
    benchmark::RegisterBenchmark(("BM_SparseFieldMeanCurvature" + R).c_str(), sparseField, r, kDefaultThreads)
        ->Iterations(iterations)->Repetitions(5)->UseRealTime()->Unit(benchmark::kMillisecond);
    for (int threads : {1, 2})
      benchmark::RegisterBenchmark(("BM_SparseFieldMeanCurvatureThreads" + R + "/" + std::to_string(threads)).c_str(),
                                   sparseField, r, threads)
          ->Iterations(iterations)->Repetitions(5)->UseRealTime()->Unit(benchmark::kMillisecond);
    // The dense box is (2R + 13)^3 voxels, values and rates: 0.56 GB at R = 200.
    benchmark::RegisterBenchmark(("BM_DenseFieldMeanCurvature" + R).c_str(), denseField, r, kDefaultThreads)
        ->Iterations(r >= 200 ? 2 : (r >= 100 ? 4 : iterations))->Repetitions(5)->UseRealTime()->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_OpenVDBLevelSetFilterMeanCurvature" + R).c_str(), openvdbFilter, r,
                                 kDefaultThreads)
        ->Iterations(r >= 200 ? 3 : (r >= 100 ? 5 : 10))->Repetitions(5)->UseRealTime()->Unit(benchmark::kMillisecond);
#if defined(LEVELFUSE_HAVE_ITK)
    benchmark::RegisterBenchmark(("BM_ITKSparseFieldMeanCurvature" + R).c_str(), itkSparseField, r, kDefaultThreads)
        ->Iterations(r >= 200 ? 2 : 4)->Repetitions(5)->UseManualTime()->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_ITKSparseFieldMeanCurvatureThreads" + R + "/1").c_str(), itkSparseField, r, 1)
        ->Iterations(r >= 200 ? 2 : 4)->Repetitions(5)->UseManualTime()->Unit(benchmark::kMillisecond);
#endif
  }
}

}  // namespace
}  // namespace levelfuse::bench

int main(int argc, char** argv) { return levelfuse::bench::runBenchmarks(argc, argv, levelfuse::bench::registerAll); }
