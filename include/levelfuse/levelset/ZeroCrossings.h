// levelfuse: the zero crossings of a sampled level set.
//
// The error measure of the paper (section 5.1.1): points where the linear
// interpolant between two adjacent grid points of opposite sign vanishes.
#pragma once

#include <openvdb/openvdb.h>

#include <cmath>
#include <vector>

namespace levelfuse {

/// World-space zero crossings along the grid edges of `grid` that touch at
/// least one of its active voxels; inside is negative.
std::vector<openvdb::Vec3d> zeroCrossings(const openvdb::FloatGrid& grid);

/// Root mean square of `distance(p)` over the points.
template <typename Distance>
double rmsOver(const std::vector<openvdb::Vec3d>& points, const Distance& distance) {
  if (points.empty()) return 0.0;
  double sum = 0.0;
  for (const openvdb::Vec3d& p : points) {
    const double d = distance(p);
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(points.size()));
}

}  // namespace levelfuse
