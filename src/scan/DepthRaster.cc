// levelfuse: triangles seen along a line of sight, as a depth image.

#include <levelfuse/scan/DepthRaster.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

namespace levelfuse {

namespace {

using openvdb::Vec3d;

/// A triangle in pixel coordinates, with what rasterising it needs.
struct PixelTriangle {
  const Vec3d* corner[3];
  double area;  ///< twice the signed area in (u, v)

  /// Barycentric weights of pixel centre (x, y) (outside the triangle some are negative).
  void weights(double x, double y, double w[3]) const {
    const Vec3d &a = *corner[0], &b = *corner[1], &c = *corner[2];
    w[0] = ((b.x() - x) * (c.y() - y) - (c.x() - x) * (b.y() - y)) / area;
    w[1] = ((c.x() - x) * (a.y() - y) - (a.x() - x) * (c.y() - y)) / area;
    w[2] = 1.0 - w[0] - w[1];
  }
  /// Depth of the triangle's plane at barycentric weights w.
  double depth(const double w[3]) const {
    return w[0] * corner[0]->z() + w[1] * corner[1]->z() + w[2] * corner[2]->z();
  }
  /// Distance in pixels from (x, y), outside the triangle, to its nearest edge.
  double distance(double x, double y) const {
    double best = std::numeric_limits<double>::max();
    for (int e = 0; e < 3; ++e) {
      const Vec3d &a = *corner[e], &b = *corner[(e + 1) % 3];
      const double dx = b.x() - a.x(), dy = b.y() - a.y();
      const double t = std::clamp(((x - a.x()) * dx + (y - a.y()) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
      best = std::min(best, std::hypot(a.x() + t * dx - x, a.y() + t * dy - y));
    }
    return best;
  }
  /// Pixels whose centres lie within `margin` of the triangle's bounding box, clamped to the image.
  void pixelBounds(double margin, int width, int height, int& x0, int& x1, int& y0, int& y1) const {
    const auto lo = [&](int axis) {
      return std::min({(*corner[0])[axis], (*corner[1])[axis], (*corner[2])[axis]}) - margin;
    };
    const auto hi = [&](int axis) {
      return std::max({(*corner[0])[axis], (*corner[1])[axis], (*corner[2])[axis]}) + margin;
    };
    x0 = static_cast<int>(std::max(0.0, std::ceil(lo(0))));
    x1 = static_cast<int>(std::min(width - 1.0, std::floor(hi(0))));
    y0 = static_cast<int>(std::max(0.0, std::ceil(lo(1))));
    y1 = static_cast<int>(std::min(height - 1.0, std::floor(hi(1))));
  }
};

}  // namespace

std::vector<float> rasteriseDepth(const std::vector<Vec3d>& vertices, const std::vector<openvdb::Vec3I>& triangles,
                                  int width, int height, double edgeExtension) {
  if (width < 1 || height < 1) throw std::invalid_argument("rasteriseDepth: the image must have pixels");
  if (!(edgeExtension >= 0.0) || !std::isfinite(edgeExtension))
    throw std::invalid_argument("rasteriseDepth: the edge extension must be finite and not negative");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::vector<PixelTriangle> projected;
  projected.reserve(triangles.size());
  for (const openvdb::Vec3I& t : triangles) {
    for (int k = 0; k < 3; ++k)
      if (t[k] >= vertices.size()) throw std::invalid_argument("rasteriseDepth: a triangle names a missing vertex");
    PixelTriangle p{{&vertices[t.x()], &vertices[t.y()], &vertices[t.z()]}, 0.0};
    p.area = (p.corner[1]->x() - p.corner[0]->x()) * (p.corner[2]->y() - p.corner[0]->y()) -
             (p.corner[2]->x() - p.corner[0]->x()) * (p.corner[1]->y() - p.corner[0]->y());
    if (std::fabs(p.area) >= 1e-12) projected.push_back(p);  // edge-on triangles cover no pixel
  }

  // Pixel centres inside a triangle: the nearest surface to the scanner wins.
  std::vector<float> depth(pixels, nan);
  for (const PixelTriangle& t : projected) {
    int x0, x1, y0, y1;
    t.pixelBounds(0.0, width, height, x0, x1, y0, y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        double w[3];
        t.weights(x, y, w);
        if (w[0] < 0.0 || w[1] < 0.0 || w[2] < 0.0) continue;
        const double z = t.depth(w);
        float& d = depth[static_cast<std::size_t>(y) * width + x];
        if (!(d == d) || z < d) d = static_cast<float>(z);
      }
  }
  if (edgeExtension == 0.0) return depth;

  // Pixel centres just outside: the plane of the nearest triangle, extrapolated
  // (the nearer to the scanner where two are as near). Never over a pixel that
  // a triangle covers.
  std::vector<float> extended(pixels, nan);
  std::vector<double> nearest(pixels, std::numeric_limits<double>::max());
  for (const PixelTriangle& t : projected) {
    int x0, x1, y0, y1;
    t.pixelBounds(edgeExtension, width, height, x0, x1, y0, y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t at = static_cast<std::size_t>(y) * width + x;
        if (depth[at] == depth[at]) continue;
        const double distance = t.distance(x, y);
        if (distance > edgeExtension || distance > nearest[at]) continue;
        double w[3];
        t.weights(x, y, w);
        const double z = t.depth(w);
        if (distance == nearest[at] && !(z < extended[at])) continue;
        nearest[at] = distance;
        extended[at] = static_cast<float>(z);
      }
  }
  for (std::size_t at = 0; at < pixels; ++at)
    if (!(depth[at] == depth[at])) depth[at] = extended[at];
  return depth;
}

}  // namespace levelfuse
