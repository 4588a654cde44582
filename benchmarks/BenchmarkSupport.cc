#include "BenchmarkSupport.h"

#include <levelfuse/levelset/ZeroCrossings.h>

#include <sys/resource.h>

namespace levelfuse::bench {

double meanRadius(const openvdb::FloatGrid& grid, const openvdb::Vec3d& centre) {
  const auto points = zeroCrossings(grid);
  double sum = 0.0;
  for (const auto& p : points) sum += (p - centre).length();
  return points.empty() ? 0.0 : sum / static_cast<double>(points.size());
}

double peakResidentMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // kilobytes on Linux
}

std::size_t iterationsFor(int radius) {
  if (radius <= 25) return 40;
  if (radius <= 50) return 30;
  if (radius <= 100) return 20;
  return 10;
}

}  // namespace levelfuse::bench
