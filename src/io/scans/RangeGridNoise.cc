// levelfuse: the noise of a range-grid scan, from the scan itself.

#include <levelfuse/io/scans/StanfordScans.h>

#include "FrameAlong.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace levelfuse::io {

namespace {

using openvdb::Vec3d;

/// Fewer full 3x3 neighbourhoods than this say too little about the noise.
constexpr std::size_t kMinNeighbourhoods = 16;

/// The residual of sample `centre` against the least-squares plane
/// z = a + b x + c y through its eight grid neighbours, divided by its
/// standard deviation in units of sigma (sqrt(1 + leverage)); false where the
/// neighbours do not span a plane.
bool standardisedResidual(const Vec3d& centre, const Vec3d (&neighbours)[8], double& residual) {
  // Normal equations in coordinates relative to the centre: the prediction at
  // the centre is then the intercept a, of variance sigma^2 (M^-1)_00.
  double m[3][3] = {}, r[3] = {};
  for (const Vec3d& q : neighbours) {
    const double row[3] = {1.0, q.x() - centre.x(), q.y() - centre.y()};
    for (int i = 0; i < 3; ++i) {
      r[i] += row[i] * (q.z() - centre.z());
      for (int j = 0; j < 3; ++j) m[i][j] += row[i] * row[j];
    }
  }
  const openvdb::math::Mat3d normal(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]);
  const double det = normal.det();
  if (!(std::fabs(det) > 1e-12 * m[1][1] * m[2][2] * m[0][0]) || !std::isfinite(det)) return false;
  const openvdb::math::Mat3d inverse = normal.inverse();
  const double a = inverse(0, 0) * r[0] + inverse(0, 1) * r[1] + inverse(0, 2) * r[2];
  residual = -a / std::sqrt(1.0 + inverse(0, 0));  // the centre is at 0 in these coordinates
  return std::isfinite(residual);
}

}  // namespace

double estimateRangeNoise(const RangeGridScan& scan, const Vec3d& towardScanner) {
  const double length = towardScanner.length();
  if (!(length > 0.0) || !std::isfinite(length)) return 0.0;
  // Coordinates with z along the line of sight, x and y across it.
  const FrameAlong axes(towardScanner);
  const auto local = [&](int index) { return axes.local(scan.points[static_cast<std::size_t>(index)]); };
  std::vector<double> residuals;
  for (int row = 1; row + 1 < scan.rows; ++row)
    for (int col = 1; col + 1 < scan.cols; ++col) {
      const int centre = scan.grid[static_cast<std::size_t>(row) * scan.cols + col];
      if (centre < 0) continue;
      Vec3d neighbours[8];
      int n = 0;
      for (int dr = -1; dr <= 1 && n >= 0; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          if (dr == 0 && dc == 0) continue;
          const int index = scan.grid[static_cast<std::size_t>(row + dr) * scan.cols + col + dc];
          if (index < 0) {
            n = -1;  // not a full neighbourhood: the edge of the scan or a dropout
            break;
          }
          neighbours[n++] = local(index);
        }
      double residual;
      if (n == 8 && standardisedResidual(local(centre), neighbours, residual)) residuals.push_back(std::fabs(residual));
    }
  if (residuals.size() < kMinNeighbourhoods) return 0.0;
  // The median absolute residual of normal noise is 0.6745 sigma; the median
  // ignores depth steps and stray samples, which are not noise.
  std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end());
  return residuals[residuals.size() / 2] / 0.6745;
}

}  // namespace levelfuse::io
