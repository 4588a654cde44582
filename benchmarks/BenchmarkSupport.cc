#include "BenchmarkSupport.h"

#include <levelfuse/levelset/ZeroCrossings.h>

#include <benchmark/benchmark.h>

#include <malloc.h>
#include <sys/resource.h>

#include <fstream>
#include <string>

namespace levelfuse::bench {

double meanRadius(const openvdb::FloatGrid& grid, const openvdb::Vec3d& centre) {
  const auto points = zeroCrossings(grid);
  double sum = 0.0;
  for (const auto& p : points) sum += (p - centre).length();
  return points.empty() ? 0.0 : sum / static_cast<double>(points.size());
}

double peakResidentMegabytes() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // kB
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // kilobytes on Linux
}

void resetPeakResident() {
  malloc_trim(0);  // what was freed leaves the resident set, or it would count again
  std::ofstream clearRefs("/proc/self/clear_refs");
  if (clearRefs) clearRefs << "5";
}

std::size_t iterationsFor(int radius) {
  if (radius <= 25) return 40;
  if (radius <= 50) return 30;
  if (radius <= 100) return 20;
  return 10;
}

int runBenchmarks(int argc, char** argv, void (*registerAll)()) {
  openvdb::initialize();
  registerAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::AddCustomContext("levelfuse_threads_default", std::to_string(kDefaultThreads));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace levelfuse::bench
