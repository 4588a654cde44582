// E57 files for tests: scans written as a scanner's software writes them (1024-
// byte pages with their CRC-32C, a binary section of data packets per scan,
// the XML section last), and the ways a file can be damaged.
#pragma once

#include "PtxFiles.h"

#include <levelfuse/scan/Colour.h>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace levelfuse::test {

/// A field of the points' prototype and its values, one per record: for an
/// Integer or ScaledInteger field, the stored integer (not scaled).
struct E57FieldSpec {
  std::string name;
  std::string type = "Float";  ///< Float, Integer or ScaledInteger
  bool single = false;         ///< a Float of single precision
  long long minimum = 0, maximum = 0;
  double scale = 1.0, offset = 0.0;
  std::vector<double> values;
};

/// One `data3D` scan.
struct E57ScanSpec {
  std::string name;
  /// The pose: a unit quaternion (w, x, y, z) and a translation; none without a pose node.
  std::optional<std::array<double, 4>> rotation;
  std::array<double, 3> translation{0.0, 0.0, 0.0};
  /// indexBounds: rowMinimum, rowMaximum, columnMinimum, columnMaximum; none without.
  std::optional<std::array<long long, 4>> indexBounds;
  std::vector<E57FieldSpec> fields;
  std::size_t packets = 3;  ///< the data packets the records are split into
  /// The recordCount the XML declares, if not the fields' value count.
  std::optional<std::uint64_t> declaredRecords;
  std::string codecs;  ///< XML inside the points' codecs (none: bit packing)
  int packetType = 1;  ///< of its packets (1: data)
};

/// Writes an E57 file of `scans` at `path`; `editXml`, if given, rewrites the
/// XML section before it is written (an XML that lies).
void writeE57(const std::string& path, const std::vector<E57ScanSpec>& scans,
              const std::function<void(std::string&)>& editXml = {});

/// A station as an E57 scan of cartesian points in scaled integers (0.1 mm),
/// rowIndex and columnIndex, cartesianInvalidState (2 where a ray had no
/// return), intensity and, if given, colours: the grid's rays on the surface
/// `range` (scanPoints), the grid's scanner as the pose. Rows are the grid's
/// elevations, columns its azimuths; indexBounds are written.
E57ScanSpec stationScan(const PtxGrid& grid, const RangeAlong& range, const std::string& name,
                        const std::vector<Rgb8>& colours = {});

/// The same station in spherical coordinates (double floats), without
/// indexBounds (the indices give the grid) and without intensity.
E57ScanSpec sphericalStationScan(const PtxGrid& grid, const RangeAlong& range, const std::string& name);

/// Flips the bits of the byte at `offset` of the file.
void flipByte(const std::string& path, std::uint64_t offset);

}  // namespace levelfuse::test
