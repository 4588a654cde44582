// PTX files for tests: surfaces seen by a scanner on a regular grid of
// azimuths and elevations, written as a scanner or an exporter writes them.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <openvdb/Types.h>
#include <openvdb/math/Mat4.h>
#include <openvdb/math/Vec3.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace levelfuse::test {

/// A scanner's grid of rays (radians) and where it stands. A scanner turns a
/// whole number of azimuth steps per turn (here 128).
struct PtxGrid {
  int columns = 24, rows = 16;
  double azimuthStart = -0.6, azimuthStep = 2.0 * M_PI / 128.0;  ///< column c looks at azimuth start + c step
  double elevationStart = -0.4, elevationStep = 0.05;  ///< row r at elevation start + r step
  /// Rows: the scanner's axes x, y, z, then its position (OpenVDB's row-vector layout).
  openvdb::math::Mat4d scannerToWorld = openvdb::math::Mat4d::identity();
};

/// The scanner at (1, 2, 3), turned 30 degrees about z.
openvdb::math::Mat4d turnedScanner();

/// The default grid (24 columns x 16 rows 0.05 rad apart) of the scanner at
/// (1, 2, 3) turned 30 degrees about z.
PtxGrid turnedGrid();

/// A level scanner at `position` whose x axis (azimuth 0) looks at `target`'s
/// vertical line.
openvdb::math::Mat4d scannerLookingAt(const openvdb::Vec3d& position, const openvdb::Vec3d& target);

/// The unit ray of column `c` and row `r` in the scanner's frame (x forward at azimuth 0, z up).
openvdb::Vec3d ptxRay(const PtxGrid& grid, int c, int r);

/// Distance along a unit ray from the scanner to a surface; 0 or less for a miss.
using RangeAlong = std::function<double(const openvdb::Vec3d& ray)>;

/// Where the rays first meet a sphere ahead of the scanner, which may stand
/// inside it or outside; scanner frame.
RangeAlong sphere(const openvdb::Vec3d& centre, double radius);

/// Where the rays meet the plane {x : normal . x = offset}; scanner frame.
RangeAlong plane(const openvdb::Vec3d& normal, double offset);

/// The sphere the station tests scan: radius 5 around the scanner, its centre
/// off the scanner (scanner frame).
inline const openvdb::Vec3d kStationSphereCentre(0.5, -0.6, 0.4);
inline constexpr double kStationSphereRadius = 5.0;
RangeAlong stationSphere();

/// The largest distance of a range map's readings (world) from the station
/// sphere around a scanner standing at `scannerToWorld`.
double farthestFromStationSphere(const levelfuse::RangeMap& map, const openvdb::math::Mat4d& scannerToWorld);

/// The grid's points on a surface in the scanner's frame, column after
/// column (a PTX scan's order); the origin where a ray misses.
std::vector<openvdb::Vec3d> scanPoints(const PtxGrid& grid, const RangeAlong& range);

/// How the points of a PTX scan are written.
enum class PtxFrame {
  kScanner,  ///< in the scanner's frame, the transform its pose (as scanners export them)
  kWorld,    ///< in the world, the transform the identity (as registration software exports them)
};

/// One scan as a PTX file writes it: the header and a line per point, "x y z
/// intensity" or, with `colours`, "x y z intensity r g b"; a miss as "0 0 0 0.5".
std::string ptxScanText(const PtxGrid& grid, const std::vector<openvdb::Vec3d>& scannerPoints, PtxFrame frame,
                        bool colours = false);

}  // namespace levelfuse::test
