// levelfuse: XYZ text point files (readXyzPoints; the format is described
// in PointScans.h).

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/scans/PointScans.h>

#include "../TextLineReader.h"

#include <cstdint>
#include <string>

namespace levelfuse::io {

namespace {

/// Lines read between two questions to the interrupter.
constexpr std::int64_t kLinesPerCheck = 1 << 16;

/// A line that holds no point: blank, or a comment.
bool holdsNoPoint(const TextLineReader& lines) {
  return lines.fieldCount() == 0 || lines.field(0).front() == '#';
}

bool isFieldCount(std::size_t fields) { return fields == 3 || fields == 4 || fields == 6 || fields == 7; }
bool hasColour(std::size_t fields) { return fields >= 6; }

/// Checks the current line's field count: one of 3, 4, 6 or 7 for the first
/// point (`fields` 0), else the first point's.
void requireFieldCount(const TextLineReader& lines, std::size_t fields, std::int64_t firstPointLine) {
  const std::size_t found = lines.fieldCount();
  if (fields == 0 && !isFieldCount(found))
    lines.fail("expected 'x y z', 'x y z intensity', 'x y z r g b' or 'x y z intensity r g b', found " +
               std::to_string(found) + " fields");
  if (fields != 0 && found != fields)
    lines.fail("expected " + std::to_string(fields) + " fields as the first point (line " +
               std::to_string(firstPointLine) + "), found " + std::to_string(found));
}

/// The intensity is checked (a finite number) but not kept.
void checkIntensity(const TextLineReader& lines) { static_cast<void>(lines.number(3)); }

}  // namespace

PointCloud readXyzPoints(const std::string& path, const Interrupter& interrupter) {
  TextLineReader lines(path);
  PointCloud cloud;
  std::size_t fields = 0;
  std::int64_t firstPointLine = 0;
  while (lines.next()) {
    if (lines.lineNumber() % kLinesPerCheck == 0) checkInterrupter(interrupter);
    if (holdsNoPoint(lines)) continue;
    requireFieldCount(lines, fields, firstPointLine);
    if (fields == 0) {
      fields = lines.fieldCount();
      firstPointLine = lines.lineNumber();
    }
    cloud.points.emplace_back(lines.number(0), lines.number(1), lines.number(2));
    if (fields == 4 || fields == 7) checkIntensity(lines);
    if (hasColour(fields)) cloud.colours.push_back(lines.colour(fields - 3));
  }
  if (cloud.points.empty()) throw InputError(path, "no points: the file is empty, blank or only comments");
  return cloud;
}

}  // namespace levelfuse::io
