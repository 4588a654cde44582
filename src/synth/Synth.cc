// levelfuse: synthetic range maps.

#include <levelfuse/synth/Synth.h>

#include <levelfuse/core/Parallel.h>

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

/// The world-space ray of pixel (u, v) of a view whose projection is `projection`.
void pixelRay(const View& view, const MapProjection& projection, int u, int v, Vec3d& origin, Vec3d& direction) {
  const PixelRay ray = projection.rayOf(u, v);
  origin = view.mapToWorld.transform(ray.origin);
  direction = view.mapToWorld.transform3x3(ray.direction);
}

void addNoise(std::vector<float>& readings, const Noise& noise) {
  if (noise.gaussianSigma <= 0.0 && noise.gaussianPerReading <= 0.0 && noise.replacementFraction <= 0.0) return;
  std::mt19937_64 rng(noise.seed);
  float lo = std::numeric_limits<float>::max(), hi = -lo;
  for (float r : readings)
    if (r == r) {
      lo = std::min(lo, r);
      hi = std::max(hi, r);
    }
  std::normal_distribution<double> gaussian(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (float& r : readings) {
    if (r != r) continue;
    if (noise.replacementFraction > 0.0 && unit(rng) < noise.replacementFraction) {
      r = static_cast<float>(lo + (hi - lo) * unit(rng));  // an outlier anywhere in the map's range
      continue;
    }
    const double sigma = noise.gaussianSigma + noise.gaussianPerReading * r;
    if (sigma > 0.0) r = static_cast<float>(r + sigma * gaussian(rng));
  }
}

RangeMap makeMap(const View& view, std::vector<float> readings, double sigma, const Noise& noise) {
  RangeMap map = view.kind == RangeMap::Kind::kOrthographic
                     ? RangeMap::orthographic(view.width, view.height, std::move(readings), view.orthographic,
                                              view.mapToWorld, sigma, view.name)
                 : view.kind == RangeMap::Kind::kPinhole
                     ? RangeMap::pinhole(view.width, view.height, std::move(readings), view.pinhole, view.mapToWorld,
                                         sigma, view.name)
                     : RangeMap::spherical(view.width, view.height, std::move(readings), view.spherical,
                                           view.mapToWorld, sigma, view.name);
  if (noise.gaussianPerReading > 0.0) map.setDepthNoise(DepthNoise{sigma, 0.0, noise.gaussianPerReading});
  map.setMissesAreEmpty(true, 0);  // a ray without a reading missed the shape
  return map;
}

/// The distance along the unit ray from the origin to triangle (a, b, c), or
/// infinity if the ray misses it (Moller and Trumbore's test).
double rayHit(const Vec3d& direction, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d e1 = b - a, e2 = c - a;
  const Vec3d p = direction.cross(e2);
  const double det = e1.dot(p);
  if (std::fabs(det) < 1e-300) return std::numeric_limits<double>::infinity();
  const Vec3d s = -a;
  const double u = s.dot(p) / det;
  if (u < 0.0 || u > 1.0) return std::numeric_limits<double>::infinity();
  const Vec3d q = s.cross(e1);
  const double v = direction.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return std::numeric_limits<double>::infinity();
  const double t = e2.dot(q) / det;
  return t > 0.0 ? t : std::numeric_limits<double>::infinity();
}

/// Casts the rays of the pixels around triangle (a, b, c) of the scanner's
/// frame, small enough in angle that its corners' pixels bound it, and keeps
/// the nearest hits in `ranges`.
void castAroundTriangle(const View& view, const Vec3d& a, const Vec3d& b, const Vec3d& c, std::vector<float>& ranges) {
  const SphericalProjection& grid = view.spherical;
  const double period = 2.0 * M_PI / std::fabs(grid.azimuthStep);
  const openvdb::math::Vec2d pa = sphericalPixel(grid, period, a), pb = sphericalPixel(grid, period, b),
                            pc = sphericalPixel(grid, period, c);
  double columns[3] = {pa.x(), pb.x(), pc.x()};
  const double rows[3] = {pa.y(), pb.y(), pc.y()};
  // A triangle across the first column: its corners on one side of it.
  if (std::max({columns[0], columns[1], columns[2]}) - std::min({columns[0], columns[1], columns[2]}) > 0.5 * period)
    for (double& column : columns)
      if (column < 0.5 * period) column += period;
  const double lo = std::min({columns[0], columns[1], columns[2]}) - 1.0;
  const double hi = std::max({columns[0], columns[1], columns[2]}) + 1.0;
  const int v0 = std::max(0, static_cast<int>(std::floor(std::min({rows[0], rows[1], rows[2]}) - 1.0)));
  const int v1 = std::min(view.height - 1, static_cast<int>(std::ceil(std::max({rows[0], rows[1], rows[2]}) + 1.0)));
  for (const double shift : {-period, 0.0, period}) {
    const int u0 = std::max(0, static_cast<int>(std::ceil(lo + shift)));
    const int u1 = std::min(view.width - 1, static_cast<int>(std::floor(hi + shift)));
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) {
        const double hit = rayHit(sphericalDirection(grid, u, v), a, b, c);
        float& r = ranges[static_cast<std::size_t>(v) * view.width + u];
        if (hit < std::numeric_limits<double>::infinity() && !(r <= hit)) r = static_cast<float>(hit);
      }
  }
}

/// A mesh seen by a spherical scanner: its triangles split (at most 16 times)
/// until each spans at most four steps of the grid as seen from the scanner,
/// each cast exactly.
std::vector<float> sphericalRangesOfMesh(const std::vector<Vec3d>& points, const std::vector<openvdb::Vec3I>& triangles,
                                         const View& view) {
  const double step = std::max(std::fabs(view.spherical.azimuthStep), std::fabs(view.spherical.elevationStep));
  const double largest = 4.0 * step;  // the angle a triangle's edges may span before it is split
  const Mat4d worldToMap = view.mapToWorld.inverse();
  std::vector<float> ranges(static_cast<std::size_t>(view.width) * static_cast<std::size_t>(view.height),
                            std::numeric_limits<float>::quiet_NaN());
  const auto angle = [](const Vec3d& p, const Vec3d& q) {
    return std::atan2(p.cross(q).length(), p.dot(q));
  };
  struct Piece {
    Vec3d a, b, c;
    int depth;
  };
  std::vector<Piece> pieces;
  for (const openvdb::Vec3I& t : triangles) {
    if (t.x() >= points.size() || t.y() >= points.size() || t.z() >= points.size())
      throw std::invalid_argument("renderMesh: a triangle index is out of range");
    pieces.push_back({worldToMap.transform(points[t.x()]), worldToMap.transform(points[t.y()]),
                      worldToMap.transform(points[t.z()]), 0});
    while (!pieces.empty()) {
      const Piece p = pieces.back();
      pieces.pop_back();
      const double span = std::max({angle(p.a, p.b), angle(p.b, p.c), angle(p.c, p.a)});
      if (span <= largest || p.depth >= 16) {
        castAroundTriangle(view, p.a, p.b, p.c, ranges);
        continue;
      }
      const Vec3d ab = 0.5 * (p.a + p.b), bc = 0.5 * (p.b + p.c), ca = 0.5 * (p.c + p.a);
      for (const Piece& q : {Piece{p.a, ab, ca, p.depth + 1}, Piece{ab, p.b, bc, p.depth + 1},
                             Piece{ca, bc, p.c, p.depth + 1}, Piece{ab, bc, ca, p.depth + 1}})
        pieces.push_back(q);
    }
  }
  return ranges;
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

View sphericalView(const Vec3d& position, double azimuthFrom, double azimuthTo, double elevationFrom,
                   double elevationTo, double stepDegrees, const std::string& name) {
  constexpr double kRadians = M_PI / 180.0;
  if (!(stepDegrees > 0.0) || !(azimuthTo > azimuthFrom) || !(elevationTo > elevationFrom) ||
      azimuthTo - azimuthFrom > 360.0 || !(elevationFrom > -90.0) || !(elevationTo < 90.0))
    throw std::invalid_argument("sphericalView: bad angles or step");
  View view;
  view.kind = RangeMap::Kind::kSpherical;
  view.width = static_cast<int>(std::lround((azimuthTo - azimuthFrom) / stepDegrees)) + 1;
  view.height = static_cast<int>(std::lround((elevationTo - elevationFrom) / stepDegrees)) + 1;
  view.spherical = SphericalProjection{azimuthFrom * kRadians, (azimuthTo - azimuthFrom) / (view.width - 1) * kRadians,
                                       elevationFrom * kRadians,
                                       (elevationTo - elevationFrom) / (view.height - 1) * kRadians};
  view.mapToWorld = rigid(Vec3d(1, 0, 0), Vec3d(0, 1, 0), Vec3d(0, 0, 1), position);
  view.name = name;
  return view;
}

View sphericalViewOf(const Vec3d& eye, const Vec3d& target, double radius, int resolution, const std::string& name) {
  constexpr double kDegrees = 180.0 / M_PI;
  const Vec3d toward = target - eye;
  const double distance = toward.length();
  if (!(radius > 0.0) || !(distance > radius) || resolution < 2)
    throw std::invalid_argument("sphericalViewOf: the scanner must stand outside the ball it scans");
  const double half = 1.1 * std::asin(radius / distance) * kDegrees;
  const double azimuth = std::atan2(toward.y(), toward.x()) * kDegrees;
  const double elevation = std::atan2(toward.z(), std::hypot(toward.x(), toward.y())) * kDegrees;
  const double across = 2.0 * half / resolution;
  const double lowest = std::max(-85.0, elevation - half), highest = std::min(85.0, elevation + half);
  // Near a pole a ball spans more azimuth than elevation.
  const double azimuthHalf = std::min(180.0, half / std::cos(std::max(std::fabs(lowest), std::fabs(highest)) / kDegrees));
  return sphericalView(eye, azimuth - azimuthHalf, azimuth + azimuthHalf, lowest, highest, across, name);
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
  const MapProjection projection = view.projection();
  const bool parallel = !projection.raysFromOneCentre();
  const double scale = parallel ? view.orthographic.pixelSize * std::max(view.width, view.height)
                                : std::fabs(signedDistance(view.mapToWorld.transform(Vec3d(0.0))));
  const double far = (parallel ? 4.0 : 400.0) * scale, tolerance = 1e-7 * scale;
  parallelFor(static_cast<std::size_t>(view.height), 1, [&](std::size_t begin, std::size_t end) {
    for (int v = static_cast<int>(begin); v < static_cast<int>(end); ++v)
      for (int u = 0; u < view.width; ++u) {
        Vec3d origin, direction;
        pixelRay(view, projection, u, v, origin, direction);
        double t = 0.0;
        for (int i = 0; i < 1000 && t < far; ++i) {
          const double d = signedDistance(origin + direction * t);
          if (d < tolerance) {
            if (d > -tolerance || i > 0)
              readings[static_cast<std::size_t>(v) * view.width + u] =
                  static_cast<float>(projection.readingAlong(u, v, t));
            break;
          }
          t += d;  // sphere tracing: the distance function bounds the free step
        }
      }
  });
  addNoise(readings, noise);
  return makeMap(view, std::move(readings), sigma, noise);
}

RangeMap renderMesh(const std::vector<Vec3d>& points, const std::vector<openvdb::Vec3I>& triangles, const View& view,
                    const Noise& noise, double sigma) {
  // Triangles are rasterised between their corners' pixels where their
  // edges stay straight in the image; a spherical grid's are cast one by one.
  const MapProjection projection = view.projection();
  if (!projection.keepsLinesStraight()) {
    std::vector<float> ranges = sphericalRangesOfMesh(points, triangles, view);
    addNoise(ranges, noise);
    return makeMap(view, std::move(ranges), sigma, noise);
  }
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
    const openvdb::math::Vec2d uv = projection.pixelOf(p);
    q = {uv.x(), uv.y(), p.z(), projection.canProject(p)};
  }
  const bool perspective = projection.raysFromOneCentre();
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
  return makeMap(view, std::move(readings), sigma, noise);
}

SurfacePaint twoColours(const openvdb::Vec3d& centre, const openvdb::Vec3d& axis, const Rgb8& above,
                        const Rgb8& below) {
  return [=](const openvdb::Vec3d& x) { return (x - centre).dot(axis) >= 0.0 ? above : below; };
}

void paintReadings(RangeMap& map, const SurfacePaint& paint) {
  std::vector<Rgb8> colours(static_cast<std::size_t>(map.width()) * map.height(), Rgb8{0, 0, 0});
  for (int v = 0; v < map.height(); ++v)
    for (int u = 0; u < map.width(); ++u)
      if (map.valid(u, v)) colours[static_cast<std::size_t>(v) * map.width() + u] = paint(map.readingPoint(u, v));
  map.setColours(std::move(colours));
}

}  // namespace levelfuse::synth
