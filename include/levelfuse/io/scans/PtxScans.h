// levelfuse: PTX files, the ASCII export of Leica's terrestrial laser scanners
// (Cyclone, Register 360) that other registration software writes too.
//
// A file holds one or more scans, each a header of ten lines and then its
// points:
//
//   columns
//   rows
//   st1 st2 st3          the scanner's registered position
//   sx1 sx2 sx3          its axis x,
//   sy1 sy2 sy3          axis y
//   sz1 sz2 sz3          and axis z (up): the scanner-to-world motion
//   r11 r12 r13 0        a rigid 4x4 transform in row-vector layout
//   r21 r22 r23 0        (world = point * M, the translation in the last row)
//   r31 r32 r33 0
//   t1  t2  t3  1
//   x y z intensity [r g b]    columns * rows lines, column after column
//
// A point "0 0 0 ..." is a ray without a return. Points are either in the
// scanner's frame with M its pose, or already in the world with M the
// identity; either way a point is taken to the world by M and from there into
// the scanner's frame by the scanner's pose, and binned by its azimuth and
// elevation into a spherical range map (scan/SphericalScan.h).
//
// The reader is strict: the file, the line and the problem are named for a
// header that is not numbers, a column or row count below 1 or more points
// than the rest of the file can hold, scanner axes that are not orthonormal,
// a transform that is not rigid, a number that is not finite, a point line of
// other than 4 or 7 fields (or of another count than the scan's first), a
// colour outside 0 to 255, a truncated file, a scan without returns, and
// anything but blank lines after the last scan.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/io/scans/PtxScan.h>
#include <levelfuse/io/scans/ScanLoadOptions.h>
#include <levelfuse/io/scans/StationGrid.h>
#include <levelfuse/scan/Colour.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/math/Mat4.h>
#include <openvdb/math/Vec3.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace levelfuse::io {

/// Takes each scan of a file as soon as it is read.
using PtxScanTaker = std::function<void(PtxScan&&)>;

/// Reads the PTX file at `path` strictly (see above), handing each scan to
/// `take` as soon as it is read: one scan is held at a time. `interrupter` is
/// asked before each scan and every 65536 points (Interrupted). Throws
/// InputError naming the file and line, also for a scan that would need more
/// memory than `budget` allows.
void readPtxScans(const std::string& path, const PtxScanTaker& take, const Interrupter& interrupter = {},
                  const MemoryBudget& budget = {});

/// The scan as a spherical range map (rangeMapFromStationGrid), a message
/// naming `path` and the scan's lines.
RangeMap rangeMapFromPtxScan(const PtxScan& scan, double sigma, const std::string& path, const std::string& name);

/// Every scan of a PTX file as a spherical range map, named "<file stem> scan
/// <k>", of noise `options.stationSigma`. With `options.take` set each is handed
/// over as soon as it is read, and none is returned. The progress is told
/// (k, k) after the k-th scan: a file does not say how many it holds.
std::vector<RangeMap> loadPtxScans(const std::string& path, const ScanLoadOptions& options = {});

}  // namespace levelfuse::io
