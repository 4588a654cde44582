// E57 files that are damaged or lie: each is refused with one message naming
// the file and what is wrong, before anything large is allocated.

#include "LargestAllocation.h"
#include "support/E57Files.h"
#include "support/Files.h"
#include "support/InputErrors.h"
#include "support/PtxFiles.h"

#include <levelfuse/io/scans/E57Scans.h>
#include <levelfuse/io/scans/Scans.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace levelfuse::io {
namespace {

using test::E57ScanSpec;

/// A small station of 24 x 16 rays (cartesian scaled integers, indices, intensity).
E57ScanSpec smallStation() {
  return test::stationScan(test::turnedGrid(), test::stationSphere(), "hall");
}

void replaceIn(std::string& xml, const std::string& from, const std::string& to) {
  const std::size_t at = xml.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  xml.replace(at, from.size(), to);
}

/// Writes the damaged file at `path`.
using Damage = std::function<void(const std::string& path)>;

void writeWith(const std::string& path, const std::function<void(E57ScanSpec&)>& change,
               const std::function<void(std::string&)>& editXml = {}) {
  E57ScanSpec scan = smallStation();
  if (change) change(scan);
  test::writeE57(path, {scan}, editXml);
}

void resize(const std::string& path, std::uintmax_t bytes) { std::filesystem::resize_file(path, bytes); }

struct DamagedFile {
  const char* name;
  Damage damage;
  const char* fragment;
};

void PrintTo(const DamagedFile& f, std::ostream* out) { *out << f.name; }

const DamagedFile kDamaged[] = {
    {"not_an_e57_file", [](const std::string& p) { test::writeText(p, std::string(2048, 'x')); },
     "not an E57 file: it starts with 'xxxxxxxx', not 'ASTM-E57'"},
    {"shorter_than_its_header", [](const std::string& p) { test::writeText(p, "ASTM-E57"); },
     "a file of 8 bytes is too short for an E57 file's 48-byte header"},
    {"cut_within_a_page",
     [](const std::string& p) {
       writeWith(p, {});
       resize(p, 3000);
     },
     "a size of 3000 bytes is not a whole number of E57's 1024-byte pages: truncated?"},
    {"cut_after_a_page",
     [](const std::string& p) {
       writeWith(p, {});
       resize(p, 2048);
     },
     "bytes long; it is 2048 (truncated?)"},
    {"a_page_whose_checksum_fails",
     [](const std::string& p) {
       writeWith(p, {});
       test::flipByte(p, 1024 + 100);
     },
     "page 1 (bytes 1024 to 2047) fails its CRC-32C checksum: the file is damaged"},
    {"xml_that_does_not_parse", [](const std::string& p) { writeWith(p, {}, [](std::string& x) { replaceIn(x, "</data3D>", ""); }); },
     "its XML section does not parse"},
    {"no_e57_root",
     [](const std::string& p) {
       writeWith(p, {}, [](std::string& x) {
         replaceIn(x, "<e57Root", "<root");
         replaceIn(x, "</e57Root>", "</root>");
       });
     },
     "its XML section has no e57Root"},
    {"no_scans",
     [](const std::string& p) { test::writeE57(p, {}); },
     "holds no 3D scans (its data3D is empty or missing)"},
    {"a_record_count_beyond_the_section",
     [](const std::string& p) { writeWith(p, [](E57ScanSpec& s) { s.declaredRecords = 1ull << 40; }); },
     "the points of scan 1 ('hall') declare 1099511627776 records, whose field 'cartesianX' alone needs more than"},
    {"a_record_count_beyond_the_bytestreams",
     [](const std::string& p) { writeWith(p, [](E57ScanSpec& s) { s.declaredRecords = 384 + 1; }); },
     "the section ends before the bytestreams hold every record"},
    {"two_to_the_forty_points_of_constant_fields",
     [](const std::string& p) {
       writeWith(p, [](E57ScanSpec& s) {
         for (test::E57FieldSpec& f : s.fields) {
           f.type = "Integer";
           f.minimum = f.maximum = 1;
           f.values.assign(f.values.size(), 1.0);
         }
         s.declaredRecords = 1ull << 40;
       });
     },
     "reading the 1099511627776 records of scan 1 ('hall') needs about"},
    {"a_file_offset_beyond_the_file",
     [](const std::string& p) {
       writeWith(p, {}, [](std::string& x) { replaceIn(x, "fileOffset=\"48\"", "fileOffset=\"99999999\""); });
     },
     "the section of the points of scan 1 ('hall') is placed at byte 99999999, beyond the file's"},
    {"a_file_offset_in_a_checksum",
     [](const std::string& p) { writeWith(p, {}, [](std::string& x) { replaceIn(x, "fileOffset=\"48\"", "fileOffset=\"1021\""); }); },
     "is placed at byte 1021, inside the checksum of page 0"},
    {"a_file_offset_that_is_no_section",
     [](const std::string& p) { writeWith(p, {}, [](std::string& x) { replaceIn(x, "fileOffset=\"48\"", "fileOffset=\"0\""); }); },
     "the section at byte 0 has id 65, not a compressed vector's (1)"},
    {"a_bit_width_over_64",
     [](const std::string& p) {
       writeWith(p, {}, [](std::string& x) { replaceIn(x, "maximum=\"2047\"", "maximum=\"36893488147419103232\""); });
     },
     "the field 'intensity''s maximum is '36893488147419103232', beyond a 64-bit integer"},
    {"an_unknown_codec",
     [](const std::string& p) { writeWith(p, [](E57ScanSpec& s) { s.codecs = "<zlibCodec type=\"Structure\"/>"; }); },
     "its points name a codec ('zlibCodec'); levelfuse reads E57's default, bit packing, alone"},
    {"a_string_field",
     [](const std::string& p) {
       writeWith(p, {}, [](std::string& x) { replaceIn(x, "<intensity type=\"Integer\"", "<intensity type=\"String\""); });
     },
     "the field 'intensity' is of type 'String', which levelfuse does not read in points"},
    {"a_float_of_half_precision",
     [](const std::string& p) {
       writeWith(p, [](E57ScanSpec& s) { s.fields.push_back(test::E57FieldSpec{"timeStamp", "Float", true, 0, 0, 1.0, 0.0, std::vector<double>(384, 0.0)}); },
                 [](std::string& x) { replaceIn(x, "precision=\"single\"", "precision=\"half\""); });
     },
     "the field 'timeStamp' has precision 'half' (expected single or double)"},
    {"a_minimum_above_its_maximum",
     [](const std::string& p) { writeWith(p, {}, [](std::string& x) { replaceIn(x, "minimum=\"0\" maximum=\"2047\"", "minimum=\"9\" maximum=\"2\""); }); },
     "the field 'intensity' has minimum 9 above its maximum 2"},
    {"no_coordinates",
     [](const std::string& p) {
       writeWith(p, {}, [](std::string& x) {
         replaceIn(x, "<cartesianX", "<x");
       });
     },
     "its points have neither cartesianX, Y and Z nor sphericalRange, Azimuth and Elevation"},
    {"a_rotation_that_is_not_a_unit_quaternion",
     [](const std::string& p) { writeWith(p, [](E57ScanSpec& s) { s.rotation = std::array<double, 4>{2.0, 0.0, 0.0, 0.0}; }); },
     "scan 1 ('hall'): its pose's rotation: the quaternion has norm 2.000000, not 1: not a rotation"},
    {"an_index_outside_the_bounds",
     [](const std::string& p) { writeWith(p, [](E57ScanSpec& s) { s.indexBounds = std::array<long long, 4>{0, 9, 0, 23}; }); },
     "scan 1 ('hall'): record 10 has row 10 and column 0, outside its grid's rows 0 to 9 and columns 0 to 23"},
    {"index_bounds_far_larger_than_the_records",
     [](const std::string& p) { writeWith(p, [](E57ScanSpec& s) { s.indexBounds = std::array<long long, 4>{0, 99999, 0, 99999}; }); },
     "scan 1 ('hall'): a grid of rows 0 to 99999 and columns 0 to 99999 has 10000000000 cells for 384 records, more "
     "than 16 per record: its indexBounds or indices are not the scanner's grid"},
    {"index_bounds_beyond_any_grid",
     [](const std::string& p) {
       writeWith(p, {}, [](std::string& x) {
         replaceIn(x, "<rowMaximum type=\"Integer\">15</rowMaximum>", "<rowMaximum type=\"Float\">1e30</rowMaximum>");
       });
     },
     "scan 1 ('hall'): its indexBounds give rowMaximum 1000000000000000019884624838656.000000, not a whole number "
     "within 2^40"},
    {"no_returns",
     [](const std::string& p) {
       writeWith(p, [](E57ScanSpec& s) { s.fields.back().values.assign(s.fields.back().values.size(), 2.0); });
     },
     "scan 1 ('hall') has no returns: none of its 384 records holds a valid position"},
    {"a_packet_of_an_unknown_type",
     [](const std::string& p) { writeWith(p, [](E57ScanSpec& s) { s.packetType = 7; }); },
     "is of type 7 (expected 0, 1 or 2: index, data or empty)"},
};

class E57Errors : public ::testing::TestWithParam<DamagedFile> {};

TEST_P(E57Errors, AreRefusedNamingTheFileAndTheProblem) {
  test::TempDir dir;
  const std::string path = dir.path("bad.e57");
  GetParam().damage(path);
  test::LargestAllocation largest;
  test::expectInputError([&] { loadScans(path); }, path, GetParam().fragment);
  EXPECT_LE(largest.bytes(), std::size_t(16) << 20);
}

std::string damageName(const ::testing::TestParamInfo<DamagedFile>& damaged) { return damaged.param.name; }

INSTANTIATE_TEST_SUITE_P(Files, E57Errors, ::testing::ValuesIn(kDamaged), damageName);

TEST(E57Errors, TheUndamagedFileReads) {
  test::TempDir dir;
  writeWith(dir.path("good.e57"), {});
  EXPECT_EQ(loadScans(dir.path("good.e57")).size(), 1u);
}

}  // namespace
}  // namespace levelfuse::io
