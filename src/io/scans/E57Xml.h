// levelfuse: the XML section of an E57 file, read into what its 3D scans are
// (private to the E57 reader).
#pragma once

#include <openvdb/math/Mat4.h>
#include <openvdb/math/Vec3.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace levelfuse::io {

/// A field of a scan's point records: one bytestream of its compressed vector.
struct E57Field {
  enum class Type { kFloat, kInteger, kScaledInteger };
  std::string name;  ///< the prototype's element name ("cartesianX"; "a/b" inside a structure)
  Type type = Type::kFloat;
  bool doublePrecision = true;  ///< of a kFloat
  /// Of a kInteger or kScaledInteger: the stored value lies in [minimum, maximum].
  std::int64_t minimum = 0, maximum = 0;
  double scale = 1.0, offset = 0.0;  ///< of a kScaledInteger: value = integer * scale + offset
  /// Bits each record takes in the bytestream (bit packing): 32 or 64 for a
  /// float, else the bits of maximum - minimum (0 when they are equal).
  int bits() const;
};

/// A scan's `points`: a compressed vector of `recordCount` records.
struct E57PointRecords {
  std::uint64_t fileOffset = 0;  ///< the physical offset of its binary section
  std::uint64_t recordCount = 0;
  std::vector<E57Field> fields;  ///< in the prototype's order: bytestream i is field i
  /// The place of the field named `name` among the fields, if there is one.
  std::optional<std::size_t> find(const std::string& name) const;
};

/// The range of a grid index (indexBounds), both ends included.
struct E57IndexRange {
  std::int64_t minimum = 0, maximum = 0;
};

/// The range of one colour channel (colorLimits).
struct E57ColourRange {
  double minimum = 0.0, maximum = 255.0;
};

/// One `data3D` scan.
struct E57ScanXml {
  std::string name;  ///< its `name` ("" without one)
  /// Its `pose`, the scan's own coordinates to the file's, in OpenVDB's
  /// row-vector layout (identity without one).
  openvdb::math::Mat4d pose = openvdb::math::Mat4d::identity();
  std::optional<E57IndexRange> rows, columns;  ///< from indexBounds, if given
  E57ColourRange colourRanges[3];               ///< red, green, blue
  E57PointRecords points;
};

/// How messages name a file's scan: "scan 1 ('pumpA')" (`index` from 1), or
/// "scan 1" for one without a name.
std::string describeE57Scan(int index, const std::string& name);

/// The 3D scans the XML section `xml` of the E57 file `path` describes.
/// Throws InputError naming the file for XML that does not parse, no
/// `e57Root` or no `data3D` scans, a scan without `points` or whose points
/// are not a compressed vector with a file offset and a record count, a field
/// of a type levelfuse does not read (strings, nested vectors), an integer
/// field whose minimum exceeds its maximum, a float precision other than
/// single or double, a codec other than bit packing, a pose whose rotation is
/// not a unit quaternion, and points with neither cartesian nor spherical
/// coordinates.
std::vector<E57ScanXml> parseE57Xml(const std::string& xml, const std::string& path);

}  // namespace levelfuse::io
