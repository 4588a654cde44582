// levelfuse: synthetic range maps.

#include <levelfuse/scan/Synth.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace levelfuse::synth {

namespace {

using openvdb::Vec3d;
using Mat4d = openvdb::math::Mat4d;

/// A rigid map-to-world matrix in OpenVDB's row-vector layout: the map's axes
/// are the rows, its origin the last row.
Mat4d rigid(const Vec3d& x, const Vec3d& y, const Vec3d& z, const Vec3d& origin) {
  return Mat4d(x.x(), x.y(), x.z(), 0.0, y.x(), y.y(), y.z(), 0.0, z.x(), z.y(), z.z(), 0.0, origin.x(), origin.y(),
               origin.z(), 1.0);
}

/// An orthonormal frame whose z axis is `forward`.
void frameAround(Vec3d forward, Vec3d& x, Vec3d& y, Vec3d& z) {
  z = forward.unit();
  const Vec3d helper = std::fabs(z.z()) < 0.9 ? Vec3d(0, 0, 1) : Vec3d(1, 0, 0);
  x = helper.cross(z).unit();
  y = z.cross(x);
}

/// The world-space ray of pixel (u, v).
void pixelRay(const View& view, int u, int v, Vec3d& origin, Vec3d& direction) {
  if (view.kind == RangeMap::Kind::kOrthographic) {
    const auto& p = view.orthographic;
    origin = view.mapToWorld.transform(Vec3d(p.origin.x() + u * p.pixelSize, p.origin.y() + v * p.pixelSize, 0.0));
    direction = view.mapToWorld.transform3x3(Vec3d(0, 0, 1));
  } else {
    const auto& p = view.pinhole;
    origin = view.mapToWorld.transform(Vec3d(0.0));
    direction = view.mapToWorld.transform3x3(Vec3d((u - p.cx) / p.fx, (v - p.cy) / p.fy, 1.0)).unit();
  }
}

/// The reading of a hit at distance t along pixel (u, v)'s ray: z for
/// orthographic maps, depth for pinhole ones.
double readingAt(const View& view, int u, int v, double t) {
  if (view.kind == RangeMap::Kind::kOrthographic) return t;
  const auto& p = view.pinhole;
  const double a = (u - p.cx) / p.fx, b = (v - p.cy) / p.fy;
  return t / std::sqrt(1.0 + a * a + b * b);
}

void addNoise(std::vector<float>& readings, const Noise& noise) {
  if (noise.gaussianSigma <= 0.0 && noise.replacementFraction <= 0.0) return;
  std::mt19937_64 rng(noise.seed);
  float lo = std::numeric_limits<float>::max(), hi = -lo;
  for (float r : readings)
    if (r == r) {
      lo = std::min(lo, r);
      hi = std::max(hi, r);
    }
  std::normal_distribution<double> gaussian(0.0, noise.gaussianSigma > 0.0 ? noise.gaussianSigma : 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (float& r : readings) {
    if (r != r) continue;
    if (noise.replacementFraction > 0.0 && unit(rng) < noise.replacementFraction) {
      r = static_cast<float>(lo + (hi - lo) * unit(rng));  // an outlier anywhere in the map's range
      continue;
    }
    if (noise.gaussianSigma > 0.0) r = static_cast<float>(r + gaussian(rng));
  }
}

RangeMap makeMap(const View& view, std::vector<float> readings, double sigma) {
  RangeMap map = view.kind == RangeMap::Kind::kOrthographic
                     ? RangeMap::orthographic(view.width, view.height, std::move(readings), view.orthographic,
                                              view.mapToWorld, sigma, view.name)
                     : RangeMap::pinhole(view.width, view.height, std::move(readings), view.pinhole, view.mapToWorld,
                                         sigma, view.name);
  map.setMissesAreEmpty(true, 0);  // a ray without a reading missed the shape
  return map;
}

}  // namespace

View orthographicView(const Vec3d& direction, const Vec3d& centre, double extent, int resolution,
                      const std::string& name) {
  if (!(extent > 0.0) || resolution < 2) throw std::invalid_argument("orthographicView: bad extent or resolution");
  Vec3d x, y, z;
  frameAround(direction, x, y, z);
  View view;
  view.kind = RangeMap::Kind::kOrthographic;
  view.width = view.height = resolution;
  view.orthographic.pixelSize = extent / resolution;
  view.orthographic.origin = openvdb::math::Vec2d(-0.5 * extent + 0.5 * view.orthographic.pixelSize);
  view.mapToWorld = rigid(x, y, z, centre - z * extent);  // the scanner plane, one extent before the centre
  view.name = name;
  return view;
}

View pinholeView(const Vec3d& eye, const Vec3d& target, double fovDegrees, int width, int height,
                 const std::string& name) {
  if (width < 2 || height < 2 || !(fovDegrees > 0.0 && fovDegrees < kWidestPinholeView))
    throw std::invalid_argument("pinholeView: bad image size or field of view");
  Vec3d x, y, z;
  frameAround(target - eye, x, y, z);
  View view;
  view.kind = RangeMap::Kind::kPinhole;
  view.width = width;
  view.height = height;
  const double f = 0.5 * width / std::tan(0.5 * fovDegrees * M_PI / 180.0);
  view.pinhole = PinholeProjection{f, f, 0.5 * (width - 1), 0.5 * (height - 1)};
  view.mapToWorld = rigid(x, y, z, eye);
  view.name = name;
  return view;
}

std::vector<View> sixAxisViews(const Vec3d& centre, double extent, int resolution) {
  const Vec3d directions[6] = {Vec3d(1, 0, 0), Vec3d(-1, 0, 0), Vec3d(0, 1, 0),
                               Vec3d(0, -1, 0), Vec3d(0, 0, 1), Vec3d(0, 0, -1)};
  const char* names[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};
  std::vector<View> views;
  for (int i = 0; i < 6; ++i)
    views.push_back(orthographicView(directions[i], centre, extent, resolution, std::string("view ") + names[i]));
  return views;
}

std::vector<View> ringViews(const Vec3d& centre, double extent, int resolution, int count, double elevationDegrees) {
  if (count < 1) throw std::invalid_argument("ringViews: no views");
  const double elevation = elevationDegrees * M_PI / 180.0;
  std::vector<View> views;
  for (int i = 0; i < count; ++i) {
    const double azimuth = 2.0 * M_PI * i / count;
    const double down = i % 2 == 0 ? -1.0 : 1.0;  // directions point away from the scanner
    const Vec3d direction(std::cos(azimuth) * std::cos(elevation), std::sin(azimuth) * std::cos(elevation),
                          down * std::sin(elevation));
    views.push_back(orthographicView(direction, centre, extent, resolution, "ring view " + std::to_string(i)));
  }
  return views;
}

std::vector<View> viewsAround(const Vec3d& centre, double extent, int resolution, int count) {
  std::vector<View> views;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (i + 0.5) * 2.0 / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Vec3d direction(std::cos(golden * i) * r, std::sin(golden * i) * r, z);
    views.push_back(orthographicView(-direction, centre, extent, resolution, "view " + std::to_string(i)));
  }
  return views;
}

RangeMap renderDistanceFunction(const std::function<double(const Vec3d&)>& signedDistance, const View& view,
                                const Noise& noise, double sigma) {
  std::vector<float> readings(static_cast<std::size_t>(view.width) * static_cast<std::size_t>(view.height),
                              std::numeric_limits<float>::quiet_NaN());
  // Scale of the scene, for the far limit and the hit tolerance: the size of
  // the scanner plane for parallel rays, the distance from the eye to the
  // nearest surface for a pinhole.
  const bool parallel = view.kind == RangeMap::Kind::kOrthographic;
  const double scale = parallel ? view.orthographic.pixelSize * std::max(view.width, view.height)
                                : std::fabs(signedDistance(view.mapToWorld.transform(Vec3d(0.0))));
  const double far = (parallel ? 4.0 : 400.0) * scale, tolerance = 1e-7 * scale;
  for (int v = 0; v < view.height; ++v)
    for (int u = 0; u < view.width; ++u) {
      Vec3d origin, direction;
      pixelRay(view, u, v, origin, direction);
      double t = 0.0;
      for (int i = 0; i < 1000 && t < far; ++i) {
        const double d = signedDistance(origin + direction * t);
        if (d < tolerance) {
          if (d > -tolerance || i > 0)
            readings[static_cast<std::size_t>(v) * view.width + u] = static_cast<float>(readingAt(view, u, v, t));
          break;
        }
        t += d;  // sphere tracing: the distance function bounds the free step
      }
    }
  addNoise(readings, noise);
  return makeMap(view, std::move(readings), sigma);
}

RangeMap renderMesh(const std::vector<Vec3d>& points, const std::vector<openvdb::Vec3I>& triangles, const View& view,
                    const Noise& noise, double sigma) {
  const std::size_t pixels = static_cast<std::size_t>(view.width) * static_cast<std::size_t>(view.height);
  std::vector<float> readings(pixels, std::numeric_limits<float>::quiet_NaN());
  const Mat4d worldToMap = view.mapToWorld.inverse();
  // Screen position (pixel units) and depth of each vertex.
  struct Projected {
    double u, v, depth;
    bool ok;
  };
  std::vector<Projected> projected(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3d p = worldToMap.transform(points[i]);
    Projected& q = projected[i];
    if (view.kind == RangeMap::Kind::kOrthographic) {
      q = {(p.x() - view.orthographic.origin.x()) / view.orthographic.pixelSize,
           (p.y() - view.orthographic.origin.y()) / view.orthographic.pixelSize, p.z(), true};
    } else {
      q = {view.pinhole.fx * p.x() / p.z() + view.pinhole.cx, view.pinhole.fy * p.y() / p.z() + view.pinhole.cy,
           p.z(), p.z() > 0.0};
    }
  }
  const bool perspective = view.kind == RangeMap::Kind::kPinhole;
  for (const openvdb::Vec3I& t : triangles) {
    if (t.x() >= points.size() || t.y() >= points.size() || t.z() >= points.size())
      throw std::invalid_argument("renderMesh: a triangle index is out of range");
    const Projected& a = projected[t.x()];
    const Projected& b = projected[t.y()];
    const Projected& c = projected[t.z()];
    if (!a.ok || !b.ok || !c.ok) continue;
    const double area = (b.u - a.u) * (c.v - a.v) - (c.u - a.u) * (b.v - a.v);
    if (std::fabs(area) < 1e-12) continue;
    const int u0 = std::max(0, static_cast<int>(std::ceil(std::min({a.u, b.u, c.u}))));
    const int u1 = std::min(view.width - 1, static_cast<int>(std::floor(std::max({a.u, b.u, c.u}))));
    const int v0 = std::max(0, static_cast<int>(std::ceil(std::min({a.v, b.v, c.v}))));
    const int v1 = std::min(view.height - 1, static_cast<int>(std::floor(std::max({a.v, b.v, c.v}))));
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) {
        // Barycentric coordinates of the pixel centre.
        const double wa = ((b.u - u) * (c.v - v) - (c.u - u) * (b.v - v)) / area;
        const double wb = ((c.u - u) * (a.v - v) - (a.u - u) * (c.v - v)) / area;
        const double wc = 1.0 - wa - wb;
        if (wa < 0.0 || wb < 0.0 || wc < 0.0) continue;
        // Depth is linear in screen space for parallel rays; its inverse for a pinhole.
        const double depth = perspective ? 1.0 / (wa / a.depth + wb / b.depth + wc / c.depth)
                                         : wa * a.depth + wb * b.depth + wc * c.depth;
        float& r = readings[static_cast<std::size_t>(v) * view.width + u];
        if (!(r == r) || depth < r) r = static_cast<float>(depth);
      }
  }
  addNoise(readings, noise);
  return makeMap(view, std::move(readings), sigma);
}

}  // namespace levelfuse::synth
