// levelfuse: the ten header lines of a PTX scan, read and checked (private
// to the PTX reader; the format is described in PtxScans.h).
#pragma once

#include "../TextLineReader.h"

#include <levelfuse/core/MemoryBudget.h>

#include <openvdb/math/Mat4.h>

#include <cstdint>
#include <string>

namespace levelfuse::io {

/// Header lines of a scan; its points follow on the next line.
inline constexpr int kPtxHeaderLines = 10;

/// Transforms and scanner axes may be off orthonormal by this much: files
/// write them with six decimals.
inline constexpr double kPtxRigidTolerance = 1e-4;

struct PtxHeader {
  int index = 0;               ///< 1 for the file's first scan
  std::int64_t firstLine = 0;  ///< the line of its column count
  int columns = 0, rows = 0;
  /// Rows x, y, z: the scanner's axes, made orthonormal to rounding; last
  /// row its position (OpenVDB's row-vector layout).
  openvdb::math::Mat4d scannerToWorld = openvdb::math::Mat4d::identity();
  /// A point as written to the world: world = point * transform.
  openvdb::math::Mat4d transform = openvdb::math::Mat4d::identity();

  std::uint64_t pointCount() const { return static_cast<std::uint64_t>(columns) * static_cast<std::uint64_t>(rows); }
  /// The line of the scan's last point (no blank line may stand among them).
  std::int64_t lastLine() const { return firstLine + kPtxHeaderLines - 1 + static_cast<std::int64_t>(pointCount()); }
  /// "scan k (lines a to b)", for messages.
  std::string describe() const;
};

/// "scan k (lines a to b)", for messages.
std::string describePtxScan(int index, std::int64_t firstLine, std::int64_t lastLine);

/// Reads the header of the scan after `previous` (of the file's first scan if
/// null) from the next line that is not blank: false if only blank lines are
/// left. Throws InputError naming the file and line for a header that is
/// malformed or truncated, axes or a transform that are not rigid, more
/// points than the rest of the file can hold or than `budget` allows, and
/// for anything but a scan after `previous` (a point line there: its columns
/// and rows disagree with its points).
bool readPtxHeader(TextLineReader& lines, const PtxHeader* previous, const MemoryBudget& budget, PtxHeader& header);

}  // namespace levelfuse::io
