// Malformed PTX files: each is refused with an InputError that names the
// file, the line and the problem, and hands over no scan.

#include "support/Files.h"
#include "support/InputErrors.h"
#include "support/PtxFiles.h"

#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/PtxScans.h>
#include <levelfuse/io/scans/Scans.h>

#include <gtest/gtest.h>

#include <cctype>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace levelfuse::io {
namespace {

using openvdb::Vec3d;
using test::PtxFrame;
using test::TempDir;
using test::writeText;

/// A valid scan of 3 columns x 4 rows of a sphere around a turned scanner:
/// lines 1 and 2 the counts, 3 the position, 4 to 6 the axes, 7 to 10 the
/// transform (the scanner's pose), 11 to 22 the points.
std::string validScan(bool colours = false) {
  test::PtxGrid grid;
  grid.columns = 3;
  grid.rows = 4;
  grid.scannerToWorld = test::turnedScanner();
  return test::ptxScanText(grid, test::scanPoints(grid, test::sphere(Vec3d(0.5, 0.0, 0.0), 4.0)),
                           PtxFrame::kScanner, colours);
}

std::vector<std::string> linesOf(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string textOf(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

/// The valid scan with line `number` (1 for the first) replaced.
std::string withLine(int number, const std::string& line, bool colours = false) {
  std::vector<std::string> lines = linesOf(validScan(colours));
  lines.at(static_cast<std::size_t>(number - 1)) = line;
  return textOf(lines);
}

/// The valid scan's first `count` lines.
std::string firstLines(std::size_t count) {
  std::vector<std::string> lines = linesOf(validScan());
  lines.resize(count);
  return textOf(lines);
}

/// The valid scan with every point a miss.
std::string withoutReturns() {
  std::vector<std::string> lines = linesOf(validScan());
  for (std::size_t i = 10; i < lines.size(); ++i) lines[i] = "0 0 0 0.5";
  return textOf(lines);
}

/// The valid scan with `text` appended to line `number`.
std::string withAppended(int number, const std::string& text, bool colours = false) {
  std::vector<std::string> lines = linesOf(validScan(colours));
  lines.at(static_cast<std::size_t>(number - 1)) += text;
  return textOf(lines);
}

struct Malformed {
  const char* name;
  std::function<std::string()> text;
  const char* fragment;  ///< what the message must say
  int scansBefore = 0;   ///< whole scans handed over before the error is found (one at a time)
};

void PrintTo(const Malformed& m, std::ostream* out) { *out << m.name; }

// clang-format off
const Malformed kMalformed[] = {
  {"empty", [] { return std::string(); }, "no scans: the file is empty or blank"},
  {"blank", [] { return std::string("\n  \n\t\n"); }, "no scans: the file is empty or blank"},
  {"not_a_ptx_file", [] { return std::string("ply\nformat ascii 1.0\n"); }, "line 1: 'ply' is not a column count (a whole number from 1 to 2147483647)"},
  {"first_line_of_two_fields", [] { return std::string("3 4\n"); }, "line 1: expected the column count of scan 1, found 2 fields: not a PTX file?"},
  {"line_without_end", [] { return std::string(5000, '7'); }, "line 1: a line longer than 4096 bytes"},
  {"zero_columns", [] { return withLine(1, "0"); }, "line 1: '0' is not a column count (a whole number from 1 to 2147483647)"},
  {"fractional_columns", [] { return withLine(1, "3.5"); }, "line 1: '3.5' is not a column count"},
  {"negative_rows", [] { return withLine(2, "-4"); }, "line 2: '-4' is not a row count (a whole number from 1 to 2147483647)"},
  {"rows_beyond_an_int", [] { return withLine(2, "4294967297"); }, "line 2: '4294967297' is not a row count"},
  {"huge_declared_size", [] { return withLine(1, "100000") ; }, "line 2: scan 1 declares 100000 columns x 4 rows, 400000 points, but the "},
  {"header_word", [] { return withLine(3, "1 two 3"); }, "line 3: 'two' is not a number"},
  {"header_two_numbers", [] { return withLine(3, "1 2"); }, "line 3: expected the scanner's position 'x y z', found 2 fields"},
  {"header_infinite", [] { return withLine(4, "inf 0 0"); }, "line 4: 'inf' is not a finite number"},
  {"header_truncated", [] { return firstLines(5); }, "the file ends in the header of scan 1, after line 5 (truncated?)"},
  {"axes_not_orthonormal", [] { return withLine(5, "0 0 1"); }, "line 6: the scanner's axes (lines 4 to 6) are not orthonormal (their dot products are off by up to 1, more than 0.0001): not a rigid motion"},
  {"axes_scaled", [] { return withLine(6, "0 0 1.001"); }, "line 6: the scanner's axes (lines 4 to 6) are not orthonormal (their dot products are off by up to 0.002"},
  {"axes_mirrored", [] { return withLine(6, "0 0 -1"); }, "line 6: the scanner's axes (lines 4 to 6) mirror space (determinant -1): not a rotation"},
  {"transform_scaled", [] { return withLine(9, "0 0 2 0"); }, "line 9: the transform's rows 1 to 3 (lines 7 to 9) are not orthonormal"},
  {"transform_mirrored", [] { return withLine(9, "0 0 -1 0"); }, "line 9: the transform's rows 1 to 3 (lines 7 to 9) mirror space (determinant -1)"},
  {"transform_projective", [] { return withLine(7, "1 0 0 0.5"); }, "line 7: the transform's last column must be 0 0 0 1 (a rigid motion, its translation in the last row), not '0.5' here"},
  {"transform_homogeneous_scale", [] { return withLine(10, "1 2 3 2"); }, "line 10: the transform's last column must be 0 0 0 1"},
  {"transform_three_numbers", [] { return withLine(8, "0 1 0"); }, "line 8: expected row 2 of the transform 'r1 r2 r3 0', found 3 fields"},
  {"point_nan", [] { return withLine(12, "nan 0 0 0.5"); }, "line 12: 'nan' is not a finite number"},
  {"point_overflow", [] { return withLine(13, "1 1e999 0 0.5"); }, "line 13: '1e999' is not a finite number"},
  {"intensity_infinite", [] { return withLine(14, "1 1 1 -inf"); }, "line 14: '-inf' is not a finite number"},
  {"intensity_beyond_a_float", [] { return withLine(14, "1 1 1 1e300"); }, "line 14: the intensity '1e300' is beyond the range of a float"},
  {"first_point_of_five_fields", [] { return withAppended(11, " 9"); }, "line 11: expected point 1 of the 12 (3 columns x 4 rows) of scan 1: 'x y z intensity' or 'x y z intensity r g b', found 5 fields"},
  {"point_of_five_fields", [] { return withAppended(13, " 9"); }, "line 13: expected point 3 of the 12 (3 columns x 4 rows) of scan 1 with 4 fields as the scan's first point (line 11), found 5 fields"},
  {"colours_after_none", [] { return withAppended(12, " 1 2 3"); }, "line 12: expected point 2 of the 12 (3 columns x 4 rows) of scan 1 with 4 fields as the scan's first point (line 11), found 7 fields"},
  {"empty_line_among_points", [] { return withLine(15, ""); }, "line 15: expected point 5 of the 12 (3 columns x 4 rows) of scan 1 with 4 fields as the scan's first point (line 11), found an empty line"},
  {"colour_above_255", [] { return withLine(12, "1 1 1 0.5 256 0 0", true); }, "line 12: '256' is not a colour (a whole number from 0 to 255)"},
  {"colour_negative", [] { return withLine(12, "1 1 1 0.5 0 -1 0", true); }, "line 12: '-1' is not a colour (a whole number from 0 to 255)"},
  {"colour_fractional", [] { return withLine(12, "1 1 1 0.5 0 0 12.5", true); }, "line 12: '12.5' is not a colour (a whole number from 0 to 255)"},
  {"truncated_points", [] { return firstLines(20); }, "the file ends after line 20, before point 11 of the 12 (3 columns x 4 rows) of scan 1 (truncated?)"},
  {"more_rows_declared_than_points", [] { return withLine(2, "5"); }, "the file ends after line 22, before point 13 of the 15 (3 columns x 5 rows) of scan 1 (truncated?)"},
  {"fewer_rows_declared_than_points", [] { return withLine(2, "3"); }, "line 20: a point line after the 9 points scan 1 (lines 1 to 19) declares (3 columns x 3 rows): its columns and rows disagree with its points", 1},
  {"no_returns", [] { return withoutReturns(); }, "scan 1 (lines 1 to 22) has no returns: all its 12 points are 0 0 0"},
  {"garbage_after_the_last_scan", [] { return validScan() + "\ngarbage\n"; }, "line 24: 'garbage' after scan 1 (lines 1 to 22): neither the column count of another scan (a whole number from 1 to 2147483647) nor the end of the file", 1},
  {"numbers_after_the_last_scan", [] { return validScan() + "1 2\n"; }, "line 23: '1 2' after scan 1 (lines 1 to 22): neither the column count of another scan", 1},
  {"second_scan_broken", [] { return validScan() + withLine(3, "1 two 3"); }, "line 25: 'two' is not a number", 1},
  {"second_scan_truncated", [] { return validScan() + firstLines(15); }, "the file ends after line 37, before point 6 of the 12 (3 columns x 4 rows) of scan 2 (truncated?)", 1},
};
// clang-format on

class MalformedPtx : public ::testing::TestWithParam<Malformed> {};

TEST_P(MalformedPtx, IsRefusedNamingTheFileTheLineAndTheProblem) {
  TempDir dir;
  const std::string path = dir.path("scan.ptx");
  writeText(path, GetParam().text());
  int taken = 0;
  test::expectInputError([&] { readPtxScans(path, [&](PtxScan&&) { ++taken; }); }, path, GetParam().fragment);
  test::expectInputError([&] { loadScans(path); }, path, GetParam().fragment);
  EXPECT_EQ(taken, GetParam().scansBefore) << "scans handed over before the error";
}

std::string malformedName(const ::testing::TestParamInfo<Malformed>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(Files, MalformedPtx, ::testing::ValuesIn(kMalformed), malformedName);

TEST(MalformedPtx, AScanWhoseReturnsMakeNoGridIsNamed) {
  TempDir dir;
  const std::string path = dir.path("column.ptx");
  test::PtxGrid grid;
  grid.columns = 1;  // no neighbours along a row: no azimuth step
  grid.rows = 12;
  writeText(path, test::ptxScanText(grid, test::scanPoints(grid, test::sphere(Vec3d(0.0), 3.0)),
                                    PtxFrame::kScanner));
  test::expectInputError([&] { loadScans(path); }, path, "scan 1 (lines 1 to 22): ");
}

TEST(MalformedPtx, AManifestEntrysNoiseMustBePositive) {
  TempDir dir;
  writeText(dir.path("scan.ptx"), validScan());
  writeText(dir.path("scans.json"), R"({"scans": [{"format": "ptx", "file": "scan.ptx", "sigma": -1}]})");
  test::expectInputError([&] { loadManifest(dir.path("scans.json")); }, dir.path("scans.json"),
                         "scans[0]: 'sigma' must be positive");
  writeText(dir.path("missing.json"), R"({"scans": [{"format": "ptx", "file": "nowhere.ptx"}]})");
  test::expectInputError([&] { loadManifest(dir.path("missing.json")); }, dir.path("missing.json"),
                         "scans[0]: 'file': no such file");
}

}  // namespace
}  // namespace levelfuse::io
