// levelfuse: spherical range maps from the points a scanner measured around
// itself (terrestrial laser scanners, spinning LiDAR).
//
// The points are given in the scanner's own frame: the scanner at the origin,
// its z axis up (the frame of a PTX scan's points, of a KITTI sweep's). Each
// point's azimuth and elevation place it on an angular grid; its distance
// from the scanner is the reading (RangeMap::spherical).
#pragma once

#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/scan/SphereAngles.h>

#include <openvdb/math/Mat4.h>
#include <openvdb/math/Vec3.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse {

/// The angles between neighbouring rays of a spherical scanner (radians, positive).
struct AngularSteps {
  AngularSteps() = default;
  AngularSteps(double azimuth, double elevation, std::vector<double> rowElevations = {})
      : azimuth(azimuth), elevation(elevation), rowElevations(std::move(rowElevations)) {}

  double azimuth = 0.0;
  double elevation = 0.0;  ///< between rows (with rowElevations: their typical spacing)
  /// The elevations of unevenly spaced rows (a spinning LiDAR's lasers),
  /// strictly increasing; empty for rows `elevation` apart.
  std::vector<double> rowElevations;
};

/// A scanner's steps on uneven rows (its lasers' elevations, radians,
/// lowest first): the elevation step is their finest spacing. Throws
/// std::invalid_argument, naming `who`, unless the rows are two or more,
/// finite and strictly increasing (requireRowElevations).
AngularSteps stepsOnRows(double azimuthStep, std::vector<double> rowElevations, const std::string& who);

/// The points binned into a spherical range map with these steps: each pixel
/// keeps the nearest point that falls in it. The grid is placed so that the
/// points lie as near their pixels' centres as they can (a scanner's own grid
/// comes back pixel for pixel), and spans the points' azimuths and
/// elevations; a full turn of azimuth is closed (the first column is repeated
/// after the last, so no seam is left). Points that are not finite, at the
/// scanner, or within kPoleMargin of a pole are left out. With uneven rows
/// (steps.rowElevations), each point goes to the row nearest its elevation
/// (rowOfElevation), the points beyond the first and the last row by more
/// than half their spacing left out. With `colours`
/// (one per point), each pixel takes its nearest point's colour
/// (RangeMap::setColours), pixels without a point black. Throws
/// std::invalid_argument for steps that are not positive and finite, row
/// elevations that are not increasing, a grid of more than 2^31 pixels, or
/// fewer than two rows or columns of points.
RangeMap sphericalMapFromPoints(const std::vector<openvdb::Vec3d>& scannerPoints, const AngularSteps& steps,
                                const openvdb::math::Mat4d& scannerToWorld, double sigma, std::string name = "",
                                const std::vector<Rgb8>& colours = {});
/// The same with sigmas that follow the range (RangeMap::setDepthNoise).
RangeMap sphericalMapFromPoints(const std::vector<openvdb::Vec3d>& scannerPoints, const AngularSteps& steps,
                                const openvdb::math::Mat4d& scannerToWorld, const DepthNoise& noise,
                                std::string name = "", const std::vector<Rgb8>& colours = {});

/// The steps of an unordered set of points in the scanner's frame (z up), as
/// a spinning LiDAR or a terrestrial scanner measured them:
///  - when the elevations come in discrete rows (a scanner's lasers, or the
///    rows of its grid), the elevation step is the typical gap between
///    neighbouring rows, and the azimuth step the typical gap between
///    neighbours within a row (so a Velodyne's 0.4 x 0.17 degrees come back
///    as they are). Rows spaced unevenly (a gap more than a quarter of a
///    step from the typical one), at most kMostUnevenRows of them (a spinning
///    LiDAR's lasers, such as the HDL-64E's two blocks a third and half a
///    degree apart), are returned as they are (rowElevations, their
///    centres), so that no laser's row is merged with another or leaves an
///    empty row between two; the elevation step is then the finer spacing;
///  - otherwise both are the mean angular spacing of the points (the side of
///    the patch of sphere a point has to itself), one point per pixel.
/// "Typical" is the median of the gaps within a quarter of a step of the
/// lower quartile of all gaps: rays without a return (gaps of two or more
/// steps) and a jitter of the angles (a few hundredths of a step) leave it
/// unchanged. Large sets are sampled evenly (at most a million elevations,
/// the azimuths of at most 32 rows): the result depends on the points and
/// their order alone. Throws std::invalid_argument for fewer than
/// kMinPointsForSteps points with a direction (finite, off the scanner and
/// its poles) or points that all look one way.
AngularSteps estimateAngularSteps(const std::vector<openvdb::Vec3d>& scannerPoints);

/// The most rows estimateAngularSteps returns as a table of uneven rows
/// (AngularSteps::rowElevations): a LiDAR's lasers, not a terrestrial grid's rows.
inline constexpr std::size_t kMostUnevenRows = 256;

/// The fewest points estimateAngularSteps takes.
inline constexpr std::size_t kMinPointsForSteps = 16;

/// The steps of a structured scan: `columns` columns of `rows` points each,
/// column after column (a PTX scan's order), in the scanner's frame, with
/// non-finite points or the origin where there was no return. Each step is the
/// median angle between neighbours of a column (elevation) or of a row
/// (azimuth) that both have a return. Throws std::invalid_argument if the
/// sizes disagree or no two neighbours along either direction have returns.
AngularSteps stepsOfGrid(const std::vector<openvdb::Vec3d>& scannerPoints, int columns, int rows);

}  // namespace levelfuse
