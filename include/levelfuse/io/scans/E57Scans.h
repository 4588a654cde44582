// levelfuse: ASTM E57 files (E2807), the exchange format of terrestrial
// laser scanners (Leica, FARO, Trimble, Riegl and the software around them).
//
// A file is 1024-byte pages, each ending in a CRC-32C of the other 1020
// bytes; a 48-byte header places an XML section that describes the file's
// `data3D` scans; each scan's points are a compressed vector of records in
// a binary section (data packets holding one bytestream per field, each
// bit-packed). levelfuse reads, of each record:
//  - its position: cartesianX, Y, Z (metres) or sphericalRange, Azimuth and
//    Elevation (metres, radians), in the scan's own frame; its `pose` (a unit
//    quaternion and a translation) takes that frame to the file's;
//  - cartesianInvalidState or sphericalInvalidState (a record that is not 0
//    has no return), and returnIndex (the first return alone is kept);
//  - rowIndex and columnIndex: the ray's place in the station's grid, whose
//    columns run along elevation (the scan is then a station, as a PTX scan
//    is); without them the records are points binned by angle around the
//    scanner (PointScans.h);
//  - intensity, and colorRed, Green, Blue scaled from the scan's
//    colorLimits to 0 to 255.
// Fields are integers, scaled integers and single or double floats, with
// E57's default codec (bit packing). Images (`images2D`) are not read.
//
// The reader is strict: a file that is not whole pages, a page whose
// checksum fails, XML that does not parse or lies about offsets and counts, a
// section that does not hold the records it declares, an unknown codec or
// field type, an index outside the scan's indexBounds and a scan without
// returns are refused with an InputError naming the file and what is wrong;
// the memory a scan needs is checked before it is allocated.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/io/scans/ScanLoadOptions.h>
#include <levelfuse/io/scans/StationGrid.h>
#include <levelfuse/scan/RangeMap.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace levelfuse::io {

/// One scan of an E57 file, its returns in the scan's own frame (the scanner
/// at the origin, z up), its pose in station.scannerToWorld.
struct E57Scan {
  int index = 0;        ///< 1 for the file's first
  std::string name;     ///< the scan's `name` ("" without one)
  std::uint64_t records = 0;  ///< the records the file declares
  /// A structured scan's grid (rowIndex, columnIndex); or, for a scan
  /// without them, columns and rows 0 and `points` (with `colours` and
  /// `intensities`) the returns alone.
  StationGrid station;
  bool structured() const { return station.columns > 0; }
};

/// Takes each scan of a file as soon as it is read.
using E57ScanTaker = std::function<void(E57Scan&&)>;

/// Reads the E57 file at `path` strictly (see above), handing each 3D scan
/// to `take` as soon as it is read: one scan is held at a time.
/// `interrupter` is asked before each data packet and every 65536 records.
/// Throws InputError naming the file, also for a scan that would need more
/// memory than `budget` allows.
void readE57Scans(const std::string& path, const E57ScanTaker& take, const Interrupter& interrupter = {},
                  const MemoryBudget& budget = {});

/// The scan as a spherical range map of noise `sigma`, named `name`: a
/// structured scan's grid as a station (rangeMapFromStationGrid), other
/// scans' points binned with the angular steps estimated from them
/// (rangeMapFromPointCloud). Throws InputError naming `path` and the scan.
RangeMap rangeMapFromE57Scan(const E57Scan& scan, double sigma, const std::string& path, const std::string& name);

/// Every scan of an E57 file as a spherical range map, named after the scan
/// (or "<file stem> scan <k>" for a scan without a name), its readings of
/// noise `options.stationSigma`. With `options.take` set each is handed over
/// as soon as it is read, and none is returned.
std::vector<RangeMap> loadE57Scans(const std::string& path, const ScanLoadOptions& options = {});

}  // namespace levelfuse::io
