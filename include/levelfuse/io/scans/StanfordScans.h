// levelfuse: the Stanford 3D Scanning Repository's range scans.
//
// A `.conf` file places each scan (`bmesh FILE tx ty tz qi qj qk qr`) in the
// world: p_world = R^T p_scan + t, R the rotation of the unit quaternion
// (w = qr). Each scan is an ASCII or binary PLY with `element vertex` (x, y, z
// in metres, scan frame) and `element range_grid` (num_rows * num_cols entries
// of 0 or 1 vertex index, row-major): the range map's 2D topology.
//
// The grid's spacing is not uniform and the file does not say how a point maps
// to a grid cell, so a scan becomes an orthographic range map by connecting
// neighbouring grid samples into triangles (skipping missing samples and
// edges much longer than the spacing: depth discontinuities) and rasterising
// them along the line of sight into a regular depth image of half the sample
// spacing, extended a pixel and a half beyond the scan's boundary so that no
// sample the triangles reach is lost.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/io/scans/LoadProgress.h>

#include <openvdb/math/Mat4.h>
#include <openvdb/math/Quat.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace levelfuse::io {

/// One `bmesh` line of a .conf file.
struct StanfordPlacement {
  std::string file;             ///< as written in the .conf
  std::string path;             ///< resolved beside the .conf
  openvdb::Vec3d translation{0.0};
  openvdb::math::Quatd rotation;  ///< unit quaternion (qi, qj, qk, qr)
  int line = 0;                 ///< line number in the .conf

  /// Scan-to-world in OpenVDB's row-vector layout: p_world = R^T p_scan + t.
  openvdb::math::Mat4d scanToWorld() const;
};

/// Reads a .conf file's `bmesh` lines (`camera` and `mesh` lines are viewer
/// entries and are skipped). Throws InputError naming the file and line for
/// malformed lines, non-finite numbers, zero or non-unit quaternions, scan
/// files that do not exist, and a .conf without scans.
std::vector<StanfordPlacement> readStanfordConf(const std::string& path);

/// A range-grid scan as stored: points in the scan frame and the grid.
struct RangeGridScan {
  std::string path;
  int rows = 0, cols = 0;
  std::vector<openvdb::Vec3d> points;  ///< scan frame, metres
  std::vector<int> grid;               ///< rows * cols entries: a point index or -1
};

/// Reads a range-grid PLY strictly: vertex coordinates finite, range_grid of
/// num_rows * num_cols entries, each empty or one index in range.
RangeGridScan readRangeGridPly(const std::string& path, const MemoryBudget& budget = {});

struct StanfordScanOptions {
  /// Asked before each scan is read: a long load can be stopped (Interrupted).
  Interrupter interrupter;
  /// If set, asked of each scan of a .conf file in order, with its place
  /// (from 0), before it is read: a scan it turns down is not read.
  std::function<bool(std::size_t)> wanted;
  /// Told after each scan of a .conf file is read.
  LoadProgress progress;
  /// The memory the reader may allocate: a scan that would need more is
  /// refused (InputError). The machine's by default.
  MemoryBudget memoryBudget;
  /// Direction from the points toward the scanner, in the scan frame (the
  /// bunny's scanner is on the +z side; the dragon's is tilted about 27 degrees
  /// toward +x: (0.46, 0.04, 0.89)).
  openvdb::Vec3d towardScanner{0.0, 0.0, 1.0};
  /// Standard deviation of a reading (metres); 0 estimates it from each scan
  /// (estimateRangeNoise), never below a hundredth of its sample spacing, and
  /// takes a quarter of the spacing for a scan too small to tell.
  double sigma = 0.0;
  /// Pixel size of the rasterised range map; 0 takes half the finer of the
  /// grid's two median sample spacings as seen along the line of sight.
  double pixelSize = 0.0;
  /// Pixels up to this far (in pixels) outside the triangles take the plane of
  /// the nearest one, so that the samples on the scan's boundary are readings
  /// of the map too (see scan/DepthRaster.h); 0 to 8.
  double edgeExtension = 1.5;
  /// Triangles with an edge longer than this many median spacings span a
  /// depth discontinuity and are skipped.
  double maxEdgeFactor = 4.0;
};

/// The noise of a scan's readings along the line of sight (metres), from the
/// scan alone: each sample with all eight grid neighbours is held against the
/// least-squares plane through them, and sigma is the median of the absolute
/// residuals (each divided by its own standard deviation in sigmas) over
/// 0.6745, which depth steps and stray samples do not move. 0 if fewer than 16
/// samples have full neighbourhoods. `towardScanner` is in the scan frame.
double estimateRangeNoise(const RangeGridScan& scan, const openvdb::Vec3d& towardScanner);

/// Median distance between neighbouring grid samples (metres); 0 if none.
double rangeGridSpacing(const RangeGridScan& scan);

/// Triangles between neighbouring grid samples, skipping missing samples and
/// triangles with an edge longer than `maxEdge` (depth discontinuities).
std::vector<openvdb::Vec3I> triangulateRangeGrid(const RangeGridScan& scan, double maxEdge);

/// Turns a range-grid scan, placed in the world, into an orthographic range map.
RangeMap rangeMapFromScan(const RangeGridScan& scan, const openvdb::math::Mat4d& scanToWorld,
                          const StanfordScanOptions& options, const std::string& name);

/// All scans of a .conf file as range maps.
std::vector<RangeMap> loadStanfordScans(const std::string& confPath, const StanfordScanOptions& options = {});

}  // namespace levelfuse::io
