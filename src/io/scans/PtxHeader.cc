// levelfuse: PTX scan headers.

#include "PtxHeader.h"

#include "../Orthonormal.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/MemoryBudget.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

namespace levelfuse::io {

namespace {

using openvdb::math::Vec3d;
using openvdb::math::Mat3d;
using openvdb::math::Mat4d;

constexpr long long kMaxCount = std::numeric_limits<int>::max();
/// A point line takes at least this many bytes: "0 0 0 0" and a line break.
constexpr std::uint64_t kMinPointLineBytes = 8;
/// Bytes held per point while a scan is read and binned: its position,
/// intensity and colour, and its share of the range map.
constexpr double kBytesPerPoint = 48.0;
const char* const kPtxTooLargeAdvice = "split the file into smaller scans, or use a machine with more memory";

/// What a line holds, for messages: "an empty line", its one field, or its field count.
std::string fieldsFound(const TextLineReader& lines) {
  if (lines.fieldCount() == 0) return "an empty line";
  if (lines.fieldCount() == 1) return quote(lines.field(0));
  return std::to_string(lines.fieldCount()) + " fields";
}

/// Moves to the next line that is not blank; false at the end of the file.
bool skipBlankLines(TextLineReader& lines) {
  while (lines.next())
    if (lines.fieldCount() > 0) return true;
  return false;
}

/// Moves to the header's next line, which must hold `fields` fields (`what` says which).
void nextHeaderLine(TextLineReader& lines, const PtxHeader& header, std::size_t fields, const std::string& what) {
  if (!lines.next())
    throw InputError(lines.path(), "the file ends in the header of scan " + std::to_string(header.index) +
                                       ", after line " + std::to_string(lines.lineNumber()) + " (truncated?)");
  if (lines.fieldCount() != fields) lines.fail("expected " + what + ", found " + fieldsFound(lines));
}

Vec3d vectorLine(TextLineReader& lines, const PtxHeader& header, const std::string& what) {
  nextHeaderLine(lines, header, 3, what);
  return Vec3d(lines.number(0), lines.number(1), lines.number(2));
}

/// The column count on the current line, the first of the scan after `previous`.
int columnCount(const TextLineReader& lines, const PtxHeader* previous) {
  if (!previous) {
    if (lines.fieldCount() != 1)
      lines.fail("expected the column count of scan 1, found " + fieldsFound(lines) + ": not a PTX file?");
    return static_cast<int>(lines.wholeNumber(0, 1, kMaxCount, "a column count (a whole number from 1 to 2147483647)"));
  }
  const std::size_t fields = lines.fieldCount();
  if (fields == 4 || fields == 7)
    lines.fail("a point line after the " + std::to_string(previous->pointCount()) + " points " + previous->describe() +
               " declares (" + std::to_string(previous->columns) + " columns x " + std::to_string(previous->rows) +
               " rows): its columns and rows disagree with its points");
  const std::optional<long long> columns = fields == 1 ? lines.wholeNumberIn(0, 1, kMaxCount) : std::nullopt;
  if (!columns)
    lines.fail(quote(lines.line()) + " after " + previous->describe() +
               ": neither the column count of another scan (a whole number from 1 to 2147483647) nor the end of "
               "the file");
  return static_cast<int>(*columns);
}

/// Fails unless the three rows just read, `what`, are orthonormal and right-handed.
void requireRotation(const TextLineReader& lines, const Mat3d& m, const std::string& what) {
  const std::string where =
      what + " (lines " + std::to_string(lines.lineNumber() - 2) + " to " + std::to_string(lines.lineNumber()) + ")";
  const double error = orthonormalityError(m);
  if (!(error <= kPtxRigidTolerance)) {
    char off[32];
    std::snprintf(off, sizeof(off), "%.3g", error);
    lines.fail(where + " are not orthonormal (their dot products are off by up to " + off +
               ", more than 0.0001): not a rigid motion");
  }
  if (m.det() < 0.0) lines.fail(where + " mirror space (determinant -1): not a rotation");
}

/// The scanner's position and axes: the scanner-to-world motion.
Mat4d scannerPose(TextLineReader& lines, const PtxHeader& header) {
  const Vec3d position = vectorLine(lines, header, "the scanner's position 'x y z'");
  const Vec3d x = vectorLine(lines, header, "the scanner's axis x 'x y z'");
  const Vec3d y = vectorLine(lines, header, "the scanner's axis y 'x y z'");
  const Vec3d z = vectorLine(lines, header, "the scanner's axis z 'x y z'");
  const Mat3d axes(x, y, z, /*rows=*/true);
  requireRotation(lines, axes, "the scanner's axes");
  Mat4d pose = Mat4d::identity();
  pose.setMat3(nearestRotation(axes));
  pose.setTranslation(position);
  return pose;
}

/// The rigid transform that takes the points to the world, row-vector layout.
Mat4d pointTransform(TextLineReader& lines, const PtxHeader& header) {
  Mat4d transform = Mat4d::identity();
  for (int row = 0; row < 4; ++row) {
    nextHeaderLine(lines, header, 4,
                   row < 3 ? "row " + std::to_string(row + 1) + " of the transform 'r1 r2 r3 0'"
                           : std::string("the transform's translation 't1 t2 t3 1'"));
    for (int column = 0; column < 4; ++column) transform(row, column) = lines.number(static_cast<std::size_t>(column));
    if (!(std::fabs(transform(row, 3) - (row < 3 ? 0.0 : 1.0)) <= kPtxRigidTolerance))
      lines.fail("the transform's last column must be 0 0 0 1 (a rigid motion, its translation in the last row), "
                 "not " + quote(lines.field(3)) + " here");
    transform(row, 3) = row < 3 ? 0.0 : 1.0;
    if (row == 2) requireRotation(lines, transform.getMat3(), "the transform's rows 1 to 3");
  }
  return transform;
}

/// Refuses more points than the rest of the file can hold, before they are allocated, or than memory can.
void requireRoomForPoints(const TextLineReader& lines, const PtxHeader& header, const MemoryBudget& budget) {
  const std::uint64_t count = header.pointCount();
  const std::uint64_t room = (lines.bytesLeft() + 1) / kMinPointLineBytes;  // the last may lack its line break
  if (count > room)
    throw InputError(lines.path(),
                     "line " + std::to_string(header.firstLine + 1) + ": scan " + std::to_string(header.index) + " declares " +
                         std::to_string(header.columns) + " columns x " + std::to_string(header.rows) + " rows, " +
                         std::to_string(count) + " points, but the " + std::to_string(lines.bytesLeft()) +
                         " bytes after its header hold at most " + std::to_string(room) +
                         " (a point line takes at least 8 bytes): a wrong count, or a truncated file");
  requireMemory(budget, lines.path(), static_cast<double>(count) * kBytesPerPoint,
                "scan " + std::to_string(header.index) + "'s " + std::to_string(count) + " points", kPtxTooLargeAdvice);
}

}  // namespace

std::string describePtxScan(int index, std::int64_t firstLine, std::int64_t lastLine) {
  return "scan " + std::to_string(index) + " (lines " + std::to_string(firstLine) + " to " + std::to_string(lastLine) +
         ")";
}

std::string PtxHeader::describe() const { return describePtxScan(index, firstLine, lastLine()); }

bool readPtxHeader(TextLineReader& lines, const PtxHeader* previous, const MemoryBudget& budget, PtxHeader& header) {
  if (!skipBlankLines(lines)) return false;
  header = PtxHeader();
  header.index = previous ? previous->index + 1 : 1;
  header.firstLine = lines.lineNumber();
  header.columns = columnCount(lines, previous);
  nextHeaderLine(lines, header, 1, "the row count of scan " + std::to_string(header.index));
  header.rows = static_cast<int>(lines.wholeNumber(0, 1, kMaxCount, "a row count (a whole number from 1 to 2147483647)"));
  header.scannerToWorld = scannerPose(lines, header);
  header.transform = pointTransform(lines, header);
  requireRoomForPoints(lines, header, budget);
  return true;
}

}  // namespace levelfuse::io
