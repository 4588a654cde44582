// levelfuse: PTX scan points.

#include "PtxPoints.h"

#include <levelfuse/io/InputError.h>

#include <cmath>
#include <limits>
#include <string>

namespace levelfuse::io {

namespace {

using openvdb::Vec3d;

/// Points read between two questions to the interrupter.
constexpr std::uint64_t kPointsPerCheck = 1 << 16;

/// Takes a point as written into the scanner's frame: to the world by the
/// scan's transform, then onto the scanner's axes from its position.
class ToScannerFrame {
 public:
  explicit ToScannerFrame(const PtxHeader& header)
      : mTransform(header.transform),
        mPosition(header.scannerToWorld.getTranslation()),
        mAxes{header.scannerToWorld.row(0).getVec3(), header.scannerToWorld.row(1).getVec3(),
              header.scannerToWorld.row(2).getVec3()} {}
  Vec3d operator()(const Vec3d& written) const {
    const Vec3d fromScanner = mTransform.transform(written) - mPosition;
    return Vec3d(fromScanner.dot(mAxes[0]), fromScanner.dot(mAxes[1]), fromScanner.dot(mAxes[2]));
  }

 private:
  openvdb::math::Mat4d mTransform;
  Vec3d mPosition;
  Vec3d mAxes[3];
};

/// "point 5 of the 12 (3 columns x 4 rows) of scan 1", for messages.
std::string pointOf(std::uint64_t i, const PtxHeader& header) {
  return "point " + std::to_string(i + 1) + " of the " + std::to_string(header.pointCount()) + " (" +
         std::to_string(header.columns) + " columns x " + std::to_string(header.rows) + " rows) of scan " +
         std::to_string(header.index);
}

/// Moves to the line of point `i` and checks its field count against the scan's (0 for its first point).
void nextPointLine(TextLineReader& lines, const PtxHeader& header, std::uint64_t i, std::size_t scanFields) {
  if (!lines.next())
    throw InputError(lines.path(), "the file ends after line " + std::to_string(lines.lineNumber()) +
                                       ", before " + pointOf(i, header) + " (truncated?)");
  const std::size_t fields = lines.fieldCount();
  if (scanFields == 0 && fields != 4 && fields != 7)
    lines.fail("expected " + pointOf(i, header) + ": 'x y z intensity' or 'x y z intensity r g b', found " +
               (fields == 0 ? std::string("an empty line") : std::to_string(fields) + " fields"));
  if (scanFields != 0 && fields != scanFields)
    lines.fail("expected " + pointOf(i, header) + " with " + std::to_string(scanFields) +
               " fields as the scan's first point (line " + std::to_string(header.firstLine + kPtxHeaderLines) +
               "), found " + (fields == 0 ? std::string("an empty line") : std::to_string(fields) + " fields"));
}

float intensityOf(const TextLineReader& lines) {
  const double value = lines.number(3);
  if (!(std::fabs(value) <= static_cast<double>(std::numeric_limits<float>::max())))
    lines.fail("the intensity " + quote(lines.field(3)) + " is beyond the range of a float");
  return static_cast<float>(value);
}

}  // namespace

PtxScan readPtxPoints(TextLineReader& lines, const PtxHeader& header, const Interrupter& interrupter) {
  const std::uint64_t count = header.pointCount();
  PtxScan scan;
  scan.index = header.index;
  scan.firstLine = header.firstLine;
  scan.lastLine = header.lastLine();
  scan.columns = header.columns;
  scan.rows = header.rows;
  scan.scannerToWorld = header.scannerToWorld;
  scan.points.reserve(count);
  scan.intensities.reserve(count);
  const ToScannerFrame toScannerFrame(header);
  std::size_t scanFields = 0;
  for (std::uint64_t i = 0; i < count; ++i) {
    if (i % kPointsPerCheck == 0) checkInterrupter(interrupter);
    nextPointLine(lines, header, i, scanFields);
    if (scanFields == 0) {
      scanFields = lines.fieldCount();
      if (scanFields == 7) scan.colours.reserve(count);
    }
    const Vec3d written(lines.number(0), lines.number(1), lines.number(2));
    scan.intensities.push_back(intensityOf(lines));
    if (scanFields == 7) scan.colours.push_back(lines.colour(4));
    const bool returned = written != Vec3d(0.0);
    scan.points.push_back(returned ? toScannerFrame(written) : Vec3d(0.0));
    if (returned) ++scan.returns;
  }
  if (scan.returns == 0)
    throw InputError(lines.path(), header.describe() + " has no returns: all its " + std::to_string(count) +
                                       " points are 0 0 0");
  return scan;
}

}  // namespace levelfuse::io
