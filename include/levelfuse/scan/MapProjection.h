// levelfuse: how a range map's pixels look into its frame: the projection of
// each kind of scanner (section 3 of the paper).
//
// In the map's own frame the lines of sight run along +z, away from the
// scanner, and a pixel (u, v) has its centre at integer coordinates:
//  - orthographic (parallel rays; laser stripe scanners): pixel (u, v) is the
//    ray x = ox + u s, y = oy + v s; its reading is the z of the surface point.
//  - pinhole (depth cameras): pixel (u, v) is the ray through
//    ((u - cx) / fx, (v - cy) / fy, 1) from the camera centre; its reading is the
//    depth z of the surface point (the Kinect / TUM / 7-Scenes convention).
//  - spherical (terrestrial laser scanners, spinning LiDAR): the scanner sits
//    at the origin with its z axis up; pixel (u, v) is the ray at azimuth
//    theta = theta0 + u dtheta (about z, from +x toward +y) and elevation
//    phi = phi0 + v dphi (from the xy plane toward +z); its reading is the
//    range, the distance from the scanner to the surface point. Here alone
//    the lines of sight do not run along +z.
//
// Each kind is a small value type (ParallelRays, PinholeRays, SphericalRays)
// that answers the same questions of a point or a pixel of the map's frame;
// MapProjection holds one of them and is the one place that tells the kinds
// apart (visit). Per-point calls are inline: loops that ask many points of
// one map may visit once and call the kind's own type inside.
#pragma once

#include <openvdb/Types.h>
#include <openvdb/math/Vec2.h>
#include <openvdb/math/Vec3.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse {

struct OrthographicProjection {
  double pixelSize = 1.0;           ///< distance between neighbouring rays (world units)
  openvdb::math::Vec2d origin{0.0};  ///< x, y of pixel (0, 0) in the map frame
};

struct PinholeProjection {
  double fx = 1.0, fy = 1.0;  ///< focal lengths in pixels
  double cx = 0.0, cy = 0.0;  ///< principal point in pixels
};

/// The angular grid of a scanner that sweeps azimuth and elevation from one
/// centre (radians). Steps may be negative (a scanner turning clockwise);
/// every row lies strictly between the poles, and the columns span at most a
/// full turn. The rows are evenly spaced, or lie at the elevations of
/// `rowElevations` (a spinning LiDAR's lasers, spaced as the sensor spaces
/// them): between two rows a fractional row is linear in elevation.
struct SphericalProjection {
  SphericalProjection() = default;
  /// Evenly spaced rows.
  SphericalProjection(double azimuthStart, double azimuthStep, double elevationStart, double elevationStep)
      : azimuthStart(azimuthStart), azimuthStep(azimuthStep), elevationStart(elevationStart),
        elevationStep(elevationStep) {}

  double azimuthStart = 0.0;    ///< azimuth of column 0
  double azimuthStep = 1e-3;    ///< from a column to the next
  double elevationStart = 0.0;  ///< elevation of row 0
  double elevationStep = 1e-3;  ///< from a row to the next (with rowElevations: their mean spacing)
  /// One elevation per row, strictly increasing; empty for evenly spaced rows.
  std::vector<double> rowElevations;
};

/// Throws std::invalid_argument, naming `who`, unless `rows` are at least two
/// elevations, finite and strictly increasing (SphericalProjection::rowElevations).
void requireRowElevations(const std::vector<double>& rows, const std::string& who);

/// The fractional row at which a spherical grid sees `elevation` (beyond the
/// first and the last of uneven rows, on the spacing of the nearest two).
inline double rowOfElevation(const SphericalProjection& p, double elevation) {
  const std::vector<double>& rows = p.rowElevations;
  if (rows.empty()) return (elevation - p.elevationStart) / p.elevationStep;
  const std::size_t below =
      static_cast<std::size_t>(std::upper_bound(rows.begin() + 1, rows.end() - 1, elevation) - rows.begin()) - 1;
  return static_cast<double>(below) + (elevation - rows[below]) / (rows[below + 1] - rows[below]);
}

/// Where a spherical grid sees a point `x` of its scanner's frame: its column,
/// counted from the first in the direction of the sweep within a turn of
/// `period` columns (2 pi / |azimuth step|), and its fractional row.
inline openvdb::math::Vec2d sphericalPixel(const SphericalProjection& p, double period, const openvdb::Vec3d& x) {
  double column = (std::atan2(x.y(), x.x()) - p.azimuthStart) / p.azimuthStep;
  column -= period * std::floor(column / period);
  const double elevation = std::atan2(x.z(), std::sqrt(x.x() * x.x() + x.y() * x.y()));
  return {column, rowOfElevation(p, elevation)};
}

/// The elevation of fractional row v (the inverse of rowOfElevation).
double elevationOfRow(const SphericalProjection& p, double v);

/// The signed elevation from row j to row j + 1 (0 <= j < rows - 1).
inline double rowStep(const SphericalProjection& p, int j) {
  if (p.rowElevations.empty()) return p.elevationStep;
  const std::size_t at = static_cast<std::size_t>(j);
  return p.rowElevations[at + 1] - p.rowElevations[at];
}

/// The largest elevation between neighbouring rows (radians, positive).
double largestRowStep(const SphericalProjection& p);

/// The unit line of sight of pixel coordinates (u, v) of a spherical grid, in
/// the scanner's frame.
openvdb::Vec3d sphericalDirection(const SphericalProjection& p, double u, double v);

/// A line of sight in a map's frame: from `origin` along the unit `direction`,
/// away from the scanner.
struct PixelRay {
  openvdb::Vec3d origin{0.0};
  openvdb::Vec3d direction{0.0, 0.0, 1.0};
};

/// Parallel rays along +z, one per pixel on a square lattice; a reading is a z.
class ParallelRays {
 public:
  ParallelRays() = default;
  explicit ParallelRays(const OrthographicProjection& p) : mP(p), mInversePixel(1.0 / p.pixelSize) {}
  const OrthographicProjection& parameters() const { return mP; }
  /// 1 / pixel size.
  double inversePixel() const { return mInversePixel; }

  bool canProject(const openvdb::Vec3d&) const { return true; }
  openvdb::math::Vec2d pixelOf(const openvdb::Vec3d& p) const {
    return {(p.x() - mP.origin.x()) / mP.pixelSize, (p.y() - mP.origin.y()) / mP.pixelSize};
  }
  /// pixelOf by a product with the inverse pixel size, as the data term's
  /// sampling finds it (it may round differently from pixelOf).
  openvdb::math::Vec2d pixelByInverse(const openvdb::Vec3d& p) const {
    return {(p.x() - mP.origin.x()) * mInversePixel, (p.y() - mP.origin.y()) * mInversePixel};
  }
  double readingOf(const openvdb::Vec3d& p) const { return p.z(); }
  PixelRay rayOf(double u, double v) const { return {pointAt(u, v, 0.0), openvdb::Vec3d(0.0, 0.0, 1.0)}; }
  openvdb::Vec3d pointAt(double u, double v, double reading) const {
    return {mP.origin.x() + u * mP.pixelSize, mP.origin.y() + v * mP.pixelSize, reading};
  }
  double readingAlong(double, double, double t) const { return t; }
  double raySpacingAt(double) const { return mP.pixelSize; }
  /// Readings may be any z: the rays reach behind the lattice's plane.
  double nearestReading(double reading, double) const { return reading; }
  /// True only if no ray of a lattice of `width` x `height` pixels passes within
  /// `radius` (plus `slack`) of `c`: the ball lies beside the lattice.
  bool missesBall(const openvdb::Vec3d& c, double radius, int width, int height, double slack) const {
    const double reach = radius + slack;
    const double x1 = mP.origin.x() + (width - 1) * mP.pixelSize, y1 = mP.origin.y() + (height - 1) * mP.pixelSize;
    return c.x() + reach < mP.origin.x() || c.x() - reach > x1 || c.y() + reach < mP.origin.y() || c.y() - reach > y1;
  }

 private:
  OrthographicProjection mP;
  double mInversePixel = 1.0;
};

/// A camera's rays from its centre through its pixels; a reading is a depth
/// along the optical axis (+z).
class PinholeRays {
 public:
  PinholeRays() = default;
  explicit PinholeRays(const PinholeProjection& p) : mP(p), mInverseFx(1.0 / p.fx), mInverseFy(1.0 / p.fy) {}
  const PinholeProjection& parameters() const { return mP; }
  /// 1 / fx and 1 / fy: the hot loops multiply where they would divide.
  double inverseFx() const { return mInverseFx; }
  double inverseFy() const { return mInverseFy; }

  /// In front of the camera: the pinhole sees nothing at or behind its plane.
  bool canProject(const openvdb::Vec3d& p) const { return p.z() > 0.0; }
  /// (fx x / z + cx, fy y / z + cy), with one division.
  openvdb::math::Vec2d pixelOf(const openvdb::Vec3d& p) const {
    const double inverseZ = 1.0 / p.z();
    return {mP.fx * p.x() * inverseZ + mP.cx, mP.fy * p.y() * inverseZ + mP.cy};
  }
  double readingOf(const openvdb::Vec3d& p) const { return p.z(); }
  /// The ray's point at depth 1 at pixel (u, v): (a, b, 1).
  double columnSlope(double u) const { return (u - mP.cx) / mP.fx; }
  double rowSlope(double v) const { return (v - mP.cy) / mP.fy; }
  PixelRay rayOf(double u, double v) const {
    return {openvdb::Vec3d(0.0), openvdb::Vec3d(columnSlope(u), rowSlope(v), 1.0).unit()};
  }
  openvdb::Vec3d pointAt(double u, double v, double reading) const {
    return pointOnRay(columnSlope(u), rowSlope(v), reading);
  }
  /// The point at depth `reading` on the ray of slopes (a, b) (columnSlope, rowSlope).
  static openvdb::Vec3d pointOnRay(double a, double b, double reading) { return {a * reading, b * reading, reading}; }
  /// The depth of the point at distance t along the ray: t / |(a, b, 1)|.
  double readingAlong(double u, double v, double t) const {
    const double a = columnSlope(u), b = rowSlope(v);
    return t / std::sqrt(1.0 + a * a + b * b);
  }
  double raySpacingAt(double reading) const { return reading / std::min(mP.fx, mP.fy); }
  /// Depths stay in front of the camera: at least a millionth of `farthest`.
  double nearestReading(double reading, double farthest) const { return std::max(reading, 1e-6 * farthest); }
  /// True only if no point within `radius` (plus `slack`) of `c` projects onto
  /// the pixels [0, width - 1] x [0, height - 1] of a `width` x `height` image:
  /// the ball lies behind the camera's plane, or beyond a plane through the
  /// camera's centre and an edge of the image (pixelOf's u = 0, u = width - 1,
  /// v = 0 or v = height - 1, each a plane n . p = 0 with n . p >= 0 inside).
  bool missesBall(const openvdb::Vec3d& c, double radius, int width, int height, double slack) const {
    const double reach = radius + slack;
    const auto beyond = [&](const openvdb::Vec3d& n) { return n.dot(c) < -reach * n.length(); };
    return c.z() + reach <= 0.0 || beyond({mP.fx, 0.0, mP.cx}) || beyond({-mP.fx, 0.0, (width - 1) - mP.cx}) ||
           beyond({0.0, mP.fy, mP.cy}) || beyond({0.0, -mP.fy, (height - 1) - mP.cy});
  }

 private:
  PinholeProjection mP;
  double mInverseFx = 1.0, mInverseFy = 1.0;
};

/// A station's rays from its centre over a grid of azimuths and elevations; a
/// reading is a range.
class SphericalRays {
 public:
  SphericalRays() = default;
  explicit SphericalRays(SphericalProjection p)
      : mP(std::move(p)), mPeriod(2.0 * M_PI / std::fabs(mP.azimuthStep)),
        mAngularStep(std::max(std::fabs(mP.azimuthStep), largestRowStep(mP))) {}
  const SphericalProjection& parameters() const { return mP; }
  /// Columns in a full turn: 2 pi / |azimuth step|.
  double azimuthPeriod() const { return mPeriod; }
  /// The larger of the two steps, the widest row spacing (radians).
  double angularStep() const { return mAngularStep; }

  /// Off the scanner's axis (x = y = 0), where a point has no azimuth.
  bool canProject(const openvdb::Vec3d& p) const { return p.x() * p.x() + p.y() * p.y() > 0.0; }
  openvdb::math::Vec2d pixelOf(const openvdb::Vec3d& p) const { return sphericalPixel(mP, mPeriod, p); }
  double readingOf(const openvdb::Vec3d& p) const { return p.length(); }
  PixelRay rayOf(double u, double v) const { return {openvdb::Vec3d(0.0), sphericalDirection(mP, u, v)}; }
  openvdb::Vec3d pointAt(double u, double v, double reading) const { return sphericalDirection(mP, u, v) * reading; }
  double readingAlong(double, double, double t) const { return t; }
  double raySpacingAt(double reading) const { return reading * mAngularStep; }
  /// Ranges are not negative.
  double nearestReading(double reading, double) const { return std::max(reading, 0.0); }
  /// Never: a station's grid is not cut to the ball's sight here.
  bool missesBall(const openvdb::Vec3d&, double, int, int, double) const { return false; }
  /// How far the rays of a tile of `du` columns and rows v0 to v1, out to
  /// `range`, reach beyond the box of their corners' points: the arcs between
  /// the corners bulge by at most range (1 - cos(the tile's diagonal angle)).
  double tileBulge(double du, double v0, double v1, double range) const {
    const double diagonal = std::hypot(du * mP.azimuthStep, elevationOfRow(mP, v1) - elevationOfRow(mP, v0));
    return range * (1.0 - std::cos(diagonal)) + 1e-9 * range;
  }

 private:
  SphericalProjection mP;
  double mPeriod = 0.0;
  double mAngularStep = 0.0;
};

/// The projection of a range map: one of the three kinds of rays, asked of
/// points and pixels of the map's frame. Built from parameters already
/// checked (RangeMap's factories check them against the map's size).
class MapProjection {
 public:
  enum class Kind { kOrthographic, kPinhole, kSpherical };

  /// Parallel rays one unit apart.
  MapProjection() = default;
  explicit MapProjection(const OrthographicProjection& p) : mKind(Kind::kOrthographic), mParallel(p) {}
  explicit MapProjection(const PinholeProjection& p) : mKind(Kind::kPinhole), mPinhole(p) {}
  explicit MapProjection(SphericalProjection p) : mKind(Kind::kSpherical), mSpherical(std::move(p)) {}
  /// The projection of `kind`, with that kind's parameters of the three
  /// (it holds the other two as given).
  static MapProjection ofKind(Kind kind, const OrthographicProjection& orthographic, const PinholeProjection& pinhole,
                              const SphericalProjection& spherical) {
    MapProjection p(spherical);
    p.mKind = kind;
    p.mParallel = ParallelRays(orthographic);
    p.mPinhole = PinholeRays(pinhole);
    return p;
  }

  Kind kind() const { return mKind; }
  /// visit(rays) with the kind's own rays (ParallelRays, PinholeRays or
  /// SphericalRays): the one place the kinds are told apart. A loop over many
  /// points of one map visits once, around the loop.
  template <typename Visit>
  decltype(auto) visit(const Visit& visit) const {
    switch (mKind) {
      case Kind::kPinhole:
        return visit(mPinhole);
      case Kind::kSpherical:
        return visit(mSpherical);
      case Kind::kOrthographic:
        break;
    }
    return visit(mParallel);
  }

  /// Whether pixelOf answers for a point: false behind a camera's pinhole (z
  /// not positive) and on a spherical scanner's axis (no azimuth), true along
  /// parallel rays.
  bool canProject(const openvdb::Vec3d& p) const {
    return visit([&](const auto& rays) { return rays.canProject(p); });
  }
  /// The fractional pixel (u, v) whose ray passes the point (may lie outside the map).
  openvdb::math::Vec2d pixelOf(const openvdb::Vec3d& p) const {
    return visit([&](const auto& rays) { return rays.pixelOf(p); });
  }
  /// What a reading of the point would be: its z along parallel rays or a
  /// camera's optical axis, its distance from a spherical scanner.
  double readingOf(const openvdb::Vec3d& p) const {
    return visit([&](const auto& rays) { return rays.readingOf(p); });
  }
  /// The line of sight of pixel coordinates (u, v) (not necessarily a pixel's centre).
  PixelRay rayOf(double u, double v) const {
    return visit([&](const auto& rays) { return rays.rayOf(u, v); });
  }
  /// The reading of the point at distance t from the ray's origin along the
  /// line of sight of pixel coordinates (u, v) (rayOf): t but for a camera,
  /// whose readings are depths.
  double readingAlong(double u, double v, double t) const {
    return visit([&](const auto& rays) { return rays.readingAlong(u, v, t); });
  }
  /// The point at pixel coordinates (u, v) with the given reading.
  openvdb::Vec3d pointAt(double u, double v, double reading) const {
    return visit([&](const auto& rays) { return rays.pointAt(u, v, reading); });
  }
  /// The distance between neighbouring rays at a reading (world units; the
  /// wider of a grid's two spacings).
  double raySpacingAt(double reading) const {
    return visit([&](const auto& rays) { return rays.raySpacingAt(reading); });
  }
  /// `reading` moved in front of the scanner where the rays start at it (a
  /// camera's depths, a station's ranges), for readings up to `farthest`.
  double nearestReading(double reading, double farthest) const {
    return visit([&](const auto& rays) { return rays.nearestReading(reading, farthest); });
  }

  /// True only if no point within `radius` (plus `slack`) of `c` projects onto
  /// the pixels of a `width` x `height` map: beside parallel rays' lattice, or
  /// behind a camera or beyond a side of its image's frustum. Never for a
  /// spherical grid.
  bool missesBall(const openvdb::Vec3d& c, double radius, int width, int height, double slack) const {
    return visit([&](const auto& rays) { return rays.missesBall(c, radius, width, height, slack); });
  }

  /// True when the lines of sight fan out from the scanner's centre (a
  /// camera, a spherical scanner), false for parallel rays.
  bool raysFromOneCentre() const { return mKind != Kind::kOrthographic; }
  /// True when straight lines project to straight lines of pixels (parallel
  /// rays, a pinhole): a convex body in front of the scanner then projects
  /// into the hull of its corners' pixels. False for a spherical grid, whose
  /// rows and columns are arcs.
  bool keepsLinesStraight() const { return mKind != Kind::kSpherical; }
  /// Columns in a full turn of a spherical grid (2 pi / |azimuth step|); 0 for the other kinds.
  double azimuthPeriod() const { return mSpherical.azimuthPeriod(); }

  /// The parameters of each kind (a single kind's projection holds the
  /// defaults for the other two).
  const OrthographicProjection& orthographic() const { return mParallel.parameters(); }
  const PinholeProjection& pinhole() const { return mPinhole.parameters(); }
  const SphericalProjection& spherical() const { return mSpherical.parameters(); }
  const ParallelRays& parallelRays() const { return mParallel; }
  const PinholeRays& pinholeRays() const { return mPinhole; }
  const SphericalRays& sphericalRays() const { return mSpherical; }

 private:
  Kind mKind = Kind::kOrthographic;
  ParallelRays mParallel;
  PinholeRays mPinhole;
  SphericalRays mSpherical;
};

/// The name of a projection, as manifests, the converter and the Python
/// module spell it: "orthographic", "pinhole" or "spherical".
const char* projectionName(MapProjection::Kind kind);

}  // namespace levelfuse
