#include "BenchmarkSupport.h"

#include <levelfuse/levelset/ZeroCrossings.h>

namespace levelfuse::bench {

double meanRadius(const openvdb::FloatGrid& grid, const openvdb::Vec3d& centre) {
  const auto points = zeroCrossings(grid);
  double sum = 0.0;
  for (const auto& p : points) sum += (p - centre).length();
  return points.empty() ? 0.0 : sum / static_cast<double>(points.size());
}

std::size_t iterationsFor(int radius) {
  if (radius <= 25) return 40;
  if (radius <= 50) return 30;
  if (radius <= 100) return 20;
  return 10;
}

}  // namespace levelfuse::bench
