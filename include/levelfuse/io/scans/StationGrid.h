// levelfuse: a terrestrial laser scanner's returns on its own grid of rays,
// as structured scan files keep them (PTX, E57 with row and column indices).
#pragma once

#include <levelfuse/scan/Colour.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/math/Mat4.h>
#include <openvdb/math/Vec3.h>

#include <cstddef>
#include <string>
#include <vector>

namespace levelfuse::io {

/// One station: `columns` columns of `rows` rays each, a column running along
/// elevation and the columns along azimuth (PTX's order, and the E57
/// standard's for a structured scan).
struct StationGrid {
  int columns = 0, rows = 0;
  /// Rows x, y, z: the scanner's axes (orthonormal to rounding), and last
  /// its position; OpenVDB's row-vector layout.
  openvdb::math::Mat4d scannerToWorld = openvdb::math::Mat4d::identity();
  /// columns * rows points, column after column, in the scanner's frame (z
  /// up); the origin where the ray had no return.
  std::vector<openvdb::Vec3d> points;
  std::vector<float> intensities;  ///< per point, as the file gives it (empty if it gives none)
  /// Per point if the file gives colours, else empty: the range map's colours.
  std::vector<Rgb8> colours;
  std::size_t returns = 0;  ///< points that are not the origin
};

/// The station as a spherical range map with the angular steps of its grid
/// (stepsOfGrid), each reading of noise `sigma`, named `name`, with the
/// points' colours if they have them. Throws InputError naming `path` and
/// `scan` (how a message names the scan: "scan 2 (lines 12 to 90)") if its
/// returns make no grid (no two neighbours along a column or a row both have
/// one), one of more than four pixels per point (refused before the map is
/// allocated), a map on which fewer than half its returns have a pixel of
/// their own (either way its points lie on no one grid), or no map.
RangeMap rangeMapFromStationGrid(const StationGrid& station, double sigma, const std::string& path,
                                 const std::string& scan, const std::string& name);

}  // namespace levelfuse::io
