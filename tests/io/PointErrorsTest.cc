// Malformed point files, KITTI files and point entries of manifests: each is
// refused with an InputError that names the file (the manifest and its entry,
// or the file at fault), the line where there is one, and the problem.

#include "support/Files.h"
#include "support/InputErrors.h"
#include "support/PointFiles.h"

#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/PointScans.h>

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace levelfuse::io {
namespace {

using openvdb::Vec3d;
using test::TempDir;
using test::writeText;

struct Malformed {
  const char* name;
  const char* file;  ///< the file `text` is written to
  std::function<std::string()> text;
  std::function<void(const std::string& path)> read;
  const char* fragment;  ///< what the message must say
};

void PrintTo(const Malformed& m, std::ostream* out) { *out << m.name; }

const auto xyz = [](const std::string& path) { readXyzPoints(path); };
const auto ply = [](const std::string& path) { readPlyPoints(path); };
const auto calib = [](const std::string& path) { readKittiVelodyneToCamera(path); };
const auto frame2 = [](const std::string& path) { readKittiCameraToWorld(path, 2); };

std::string text(const char* t) { return t; }

const char* const kIdentity = "1 0 0 0 0 1 0 0 0 0 1 0";
const char* const kPlyHeader = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n";

// clang-format off
const Malformed kMalformed[] = {
  {"xyz_empty", "a.xyz", [] { return text(""); }, xyz, "no points: the file is empty, blank or only comments"},
  {"xyz_only_comments", "a.xyz", [] { return text("# x y z\n\n"); }, xyz, "no points: the file is empty, blank or only comments"},
  {"xyz_word", "a.xyz", [] { return text("1 2 3\n1 two 3\n"); }, xyz, "line 2: 'two' is not a number"},
  {"xyz_nan", "a.xyz", [] { return text("1 2 nan\n"); }, xyz, "line 1: 'nan' is not a finite number"},
  {"xyz_infinite_intensity", "a.xyz", [] { return text("1 2 3 inf\n"); }, xyz, "line 1: 'inf' is not a finite number"},
  {"xyz_two_fields", "a.xyz", [] { return text("1 2\n"); }, xyz, "line 1: expected 'x y z', 'x y z intensity', 'x y z r g b' or 'x y z intensity r g b', found 2 fields"},
  {"xyz_five_fields", "a.xyz", [] { return text("1 2 3 4 5\n"); }, xyz, "found 5 fields"},
  {"xyz_mixed_field_counts", "a.xyz", [] { return text("# points\n1 2 3\n4 5 6 7\n"); }, xyz, "line 3: expected 3 fields as the first point (line 2), found 4"},
  {"xyz_colour_300", "a.xyz", [] { return text("1 2 3 0 0 0\n1 2 3 300 0 0\n"); }, xyz, "line 2: '300' is not a colour (a whole number from 0 to 255)"},
  {"xyz_colour_fractional", "a.xyz", [] { return text("1 2 3 0.5 0 0 12.5\n"); }, xyz, "line 1: '12.5' is not a colour"},
  {"xyz_line_without_end", "a.xyz", [] { return std::string(5000, '1'); }, xyz, "line 1: a line longer than 4096 bytes"},
  {"ply_no_vertex", "a.ply", [] { return text("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"); }, ply, "no 'vertex' element: no points"},
  {"ply_no_x", "a.ply", [] { return text("ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nproperty float z\nend_header\n1 2\n"); }, ply, "the vertices have no x, y and z"},
  {"ply_list_x", "a.ply", [] { return text("ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nproperty float y\nproperty float z\nend_header\n1 1 2 3\n"); }, ply, "the vertex property 'x' is a list, not a number"},
  {"ply_empty_vertex", "a.ply", [] { return text("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n"); }, ply, "no points: the 'vertex' element is empty"},
  {"ply_nan", "a.ply", [] { return std::string(kPlyHeader) + "end_header\n1 2 3\n1 nan 3\n"; }, ply, "vertex 1 has a coordinate that is not finite"},
  {"ply_red_alone", "a.ply", [] { return std::string(kPlyHeader) + "property uchar red\nend_header\n1 2 3 4\n1 2 3 4\n"; }, ply, "the vertices have some of 'red', 'green' and 'blue' but not all three"},
  {"ply_colours_of_ushort", "a.ply", [] { return std::string(kPlyHeader) + "property ushort red\nproperty ushort green\nproperty ushort blue\nend_header\n1 2 3 4 5 6\n1 2 3 4 5 6\n"; }, ply, "the vertex colours must all be uchar (0 to 255) or all float or double (0 to 1)"},
  {"ply_float_colour_above_1", "a.ply", [] { return std::string(kPlyHeader) + "property float red\nproperty float green\nproperty float blue\nend_header\n1 2 3 0 0 0\n1 2 3 0 1.5 0\n"; }, ply, "vertex 1: green 1.500000 is outside 0 to 1 (a float colour)"},
  {"ply_huge_vertex_count", "a.ply", [] { return text("ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0123456789ab"); }, ply, "element 'vertex' declares 4000000000 entries, but only 12 bytes follow the header"},
  {"calib_without_tr", "calib.txt", [] { return text("P0: 1 0 0 0 0 1 0 0 0 0 1 0\n"); }, calib, "no 'Tr:' line: KITTI odometry's calib.txt gives the velodyne-to-camera-0 transform there"},
  {"calib_tr_of_eleven_numbers", "calib.txt", [] { return text("Tr: 1 0 0 0 0 1 0 0 0 0 1\n"); }, calib, "line 1: expected 'Tr:' (velodyne to camera 0): 12 numbers (a 3x4 transform row by row), found 11"},
  {"calib_tr_scaled", "calib.txt", [] { return text("P0: 1 2 3\nTr: 2 0 0 0 0 1 0 0 0 0 1 0\n"); }, calib, "line 2: 'Tr:' (velodyne to camera 0): the pose's rotation is not orthonormal: not a rigid motion"},
  {"calib_tr_mirrored", "calib.txt", [] { return text("Tr: -1 0 0 0 0 1 0 0 0 0 1 0\n"); }, calib, "line 1: 'Tr:' (velodyne to camera 0): the pose mirrors space (determinant -1)"},
  {"calib_two_trs", "calib.txt", [] { return std::string("Tr: ") + kIdentity + "\n\nTr: " + kIdentity + "\n"; }, calib, "line 3: a second 'Tr:' line (the first is line 1)"},
  {"calib_raw_kitti_file", "calib.txt", [] { return text("calib_time: 15-Mar-2012 11:37:16\n"); }, calib, "line 1: '15-Mar-2012' is not a number"},
  {"calib_no_key", "calib.txt", [] { return text("1 0 0 0 0 1 0 0 0 0 1 0\n"); }, calib, "line 1: expected 'NAME: numbers' (KITTI odometry's calib.txt), found '1'"},
  {"poses_empty", "00.txt", [] { return text("\n"); }, frame2, "no poses: the file is empty or blank"},
  {"poses_frame_beyond_the_file", "00.txt", [] { return std::string(kIdentity) + "\n" + kIdentity + "\n"; }, frame2, "frame 2 is beyond the file's 2 poses (frames 0 to 1)"},
  {"poses_of_eleven_numbers", "00.txt", [] { return std::string(kIdentity) + "\n1 0 0 0 0 1 0 0 0 0 1\n"; }, frame2, "line 2: expected the pose of frame 1: 12 numbers (a 3x4 transform row by row), found 11"},
  {"poses_sheared", "00.txt", [] { return std::string(kIdentity) + "\n1 0.5 0 0 0 1 0 0 0 0 1 0\n"; }, frame2, "line 2: the pose of frame 1: the pose's rotation is not orthonormal: not a rigid motion"},
  {"poses_nan", "00.txt", [] { return text("1 0 0 nan 0 1 0 0 0 0 1 0\n"); }, frame2, "line 1: 'nan' is not a finite number"},
  {"poses_blank_line_among_them", "00.txt", [] { return std::string(kIdentity) + "\n\n" + kIdentity + "\n"; }, frame2, "line 3: a pose after the blank line 2: the file holds one line per frame, frame 0 on line 1"},
};
// clang-format on

class MalformedPoints : public ::testing::TestWithParam<Malformed> {};

TEST_P(MalformedPoints, IsRefusedNamingTheFileAndTheProblem) {
  TempDir dir;
  const std::string path = dir.path(GetParam().file);
  writeText(path, GetParam().text());
  test::expectInputError([&] { GetParam().read(path); }, path, GetParam().fragment);
}

std::string malformedName(const ::testing::TestParamInfo<Malformed>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(Files, MalformedPoints, ::testing::ValuesIn(kMalformed), malformedName);

TEST(MalformedKittiBin, ASizeThatIsNotAWholeNumberOfPointsIsNamed) {
  TempDir dir;
  std::vector<unsigned char> bytes = test::kittiBinBytes({Vec3d(1, 2, 3), Vec3d(4, 5, 6)});
  bytes.resize(20);
  test::writeBytes(dir.path("a.bin"), bytes);
  test::expectInputError([&] { readKittiBin(dir.path("a.bin")); }, dir.path("a.bin"),
                         "a size of 20 bytes is not a whole number of points of 16 bytes (x y z reflectance, "
                         "float32): truncated, or not a KITTI velodyne file");
  test::writeBytes(dir.path("empty.bin"), {});
  test::expectInputError([&] { readKittiBin(dir.path("empty.bin")); }, dir.path("empty.bin"),
                         "no points: the file is empty");
}

TEST(MalformedKittiBin, NonFiniteValuesAreNamedWithTheirPoint) {
  TempDir dir;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::vector<unsigned char> bytes = test::kittiBinBytes({Vec3d(1, 2, 3), Vec3d(4, 5, 6), Vec3d(7, 8, 9)});
  std::memcpy(bytes.data() + 2 * 16 + 4, &nan, 4);
  test::writeBytes(dir.path("nan.bin"), bytes);
  test::expectInputError([&] { readKittiBin(dir.path("nan.bin")); }, dir.path("nan.bin"),
                         "point 2 (at byte 32) has a coordinate that is not finite");
  bytes = test::kittiBinBytes({Vec3d(1, 2, 3)});
  std::memcpy(bytes.data() + 12, &inf, 4);
  test::writeBytes(dir.path("inf.bin"), bytes);
  test::expectInputError([&] { readKittiBin(dir.path("inf.bin")); }, dir.path("inf.bin"),
                         "point 0 (at byte 0) has a reflectance that is not finite");
}

struct BadEntry {
  const char* name;
  const char* entry;     ///< the manifest's one entry
  const char* fragment;  ///< what the message must say
};

void PrintTo(const BadEntry& b, std::ostream* out) { *out << b.name; }

// clang-format off
const BadEntry kBadEntries[] = {
  {"no_placement", R"({"format": "points", "file": "a.xyz"})", "scans[0]: missing the sensor's 'origin' [x, y, z] or its 'pose' (or 'pose_file')"},
  {"origin_and_pose", R"({"format": "points", "file": "a.xyz", "origin": [0, 0, 0], "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]})", "scans[0]: give one of the sensor's 'origin', 'pose' and 'pose_file', not 2"},
  {"origin_of_two_numbers", R"({"format": "points", "file": "a.xyz", "origin": [0, 0]})", "scans[0]: 'origin' needs 3 numbers"},
  {"pose_scaled", R"({"format": "points", "file": "a.xyz", "pose": [2,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]})", "scans[0]: the pose's rotation is not orthonormal: not a rigid motion"},
  {"pose_mirrored", R"({"format": "points", "file": "a.xyz", "pose": [1,0,0,0, 0,1,0,0, 0,0,-1,0, 0,0,0,1]})", "scans[0]: the pose mirrors space (determinant -1)"},
  {"azimuth_step_alone", R"({"format": "points", "file": "a.xyz", "origin": [0, 0, 0], "azimuth_step": 0.1})", "scans[0]: give both 'azimuth_step' and 'elevation_step' (degrees), or neither"},
  {"step_of_zero", R"({"format": "points", "file": "a.xyz", "origin": [0, 0, 0], "azimuth_step": 0, "elevation_step": 0.1})", "scans[0]: 'azimuth_step' must be positive"},
  {"step_of_200_degrees", R"({"format": "points", "file": "a.xyz", "origin": [0, 0, 0], "azimuth_step": 200, "elevation_step": 0.1})", "scans[0]: 'azimuth_step' must be less than 180 degrees"},
  {"rows_and_elevation_step", R"({"format": "points", "file": "a.xyz", "origin": [0, 0, 0], "azimuth_step": 0.1, "elevation_step": 0.1, "row_elevations": [0, 1]})", "scans[0]: give 'elevation_step' or 'row_elevations', not both"},
  {"rows_without_azimuth_step", R"({"format": "points", "file": "a.xyz", "origin": [0, 0, 0], "row_elevations": [0, 1]})", "scans[0]: 'row_elevations' needs the 'azimuth_step' (degrees) beside it"},
  {"one_row", R"({"format": "points", "file": "a.xyz", "origin": [0, 0, 0], "azimuth_step": 0.1, "row_elevations": [0]})", "scans[0]: 'row_elevations' needs two or more elevations (degrees, one per laser, lowest first)"},
  {"rows_decreasing", R"({"format": "kitti-bin", "file": "a.bin", "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "azimuth_step": 0.1, "row_elevations": [1, 0.5, 0]})", "scans[0]: 'row_elevations': the row elevations must be finite and strictly increasing (row 1)"},
  {"row_at_the_pole", R"({"format": "points", "file": "a.xyz", "origin": [0, 0, 0], "azimuth_step": 0.1, "row_elevations": [0, 90]})", "scans[0]: 'row_elevations' must lie strictly between -90 and 90 degrees"},
  {"negative_sigma", R"({"format": "points", "file": "a.xyz", "origin": [0, 0, 0], "sigma": -1})", "scans[0]: 'sigma' must be positive"},
  {"unknown_coordinates", R"({"format": "points", "file": "a.xyz", "origin": [0, 0, 0], "coordinates": "camera"})", "scans[0]: 'coordinates' must be \"world\" or \"sensor\", not 'camera'"},
  {"misspelt_field", R"({"format": "points", "file": "a.xyz", "orign": [0, 0, 0]})", "scans[0]: unknown field 'orign' for its format (expected format, file, origin, pose, pose_file, coordinates, azimuth_step, elevation_step, row_elevations, sigma, misses_are_empty, dropout_reach)"},
  {"unknown_point_file_type", R"({"format": "points", "file": "a.bin", "origin": [0, 0, 0]})", "unknown point file type '.bin' (expected .xyz, .txt or .ply)"},
  {"kitti_pose_and_poses", R"({"format": "kitti-bin", "file": "a.bin", "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "poses": "00.txt"})", "scans[0]: give the velodyne's 'pose' (or 'pose_file') or KITTI odometry's 'poses', 'calib' and 'frame', not both"},
  {"kitti_no_pose", R"({"format": "kitti-bin", "file": "a.bin"})", "scans[0]: missing the velodyne's 'pose' (or 'pose_file'), or KITTI odometry's 'poses', 'calib' and 'frame'"},
  {"kitti_poses_without_calib", R"({"format": "kitti-bin", "file": "a.bin", "poses": "00.txt", "frame": 0})", "scans[0]: missing 'calib': KITTI odometry's poses need 'poses', 'calib' and 'frame'"},
  {"kitti_fractional_frame", R"({"format": "kitti-bin", "file": "a.bin", "poses": "00.txt", "calib": "calib.txt", "frame": 1.5})", "scans[0]: 'frame' must be a whole number from 0"},
  {"kitti_origin", R"({"format": "kitti-bin", "file": "a.bin", "origin": [0, 0, 0]})", "scans[0]: unknown field 'origin' for its format"},
};
// clang-format on

class BadPointEntry : public ::testing::TestWithParam<BadEntry> {};

TEST_P(BadPointEntry, IsRefusedNamingTheManifestAndTheEntry) {
  TempDir dir;
  writeText(dir.path("a.xyz"), "1 2 3\n");
  test::writeBytes(dir.path("a.bin"), test::kittiBinBytes({Vec3d(1, 2, 3)}));
  writeText(dir.path("00.txt"), std::string(kIdentity) + "\n");
  writeText(dir.path("calib.txt"), std::string("Tr: ") + kIdentity + "\n");
  writeText(dir.path("scans.json"), std::string(R"({"scans": [)") + GetParam().entry + "]}");
  const std::string culprit = std::string(GetParam().fragment).rfind("scans[0]", 0) == 0 ? dir.path("scans.json")
                                                                                       : dir.path("a.bin");
  test::expectInputError([&] { loadManifest(dir.path("scans.json")); }, culprit, GetParam().fragment);
}

std::string badEntryName(const ::testing::TestParamInfo<BadEntry>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(Manifests, BadPointEntry, ::testing::ValuesIn(kBadEntries), badEntryName);

TEST(BadPointEntry, AFrameBeyondThePosesFileNamesThePosesFile) {
  TempDir dir;
  test::writeBytes(dir.path("a.bin"), test::kittiBinBytes({Vec3d(1, 2, 3)}));
  writeText(dir.path("00.txt"), std::string(kIdentity) + "\n");
  writeText(dir.path("calib.txt"), std::string("Tr: ") + kIdentity + "\n");
  writeText(dir.path("scans.json"), R"({"scans": [{"format": "kitti-bin", "file": "a.bin", "poses": "00.txt",
      "calib": "calib.txt", "frame": 7}]})");
  test::expectInputError([&] { loadManifest(dir.path("scans.json")); }, dir.path("00.txt"),
                         "frame 7 is beyond the file's 1 poses (frames 0 to 0)");
}

TEST(BadPointCloud, StepsFarFinerThanThePointsAreRefusedBeforeTheMapIsMade) {
  std::vector<Vec3d> points;
  for (int i = 0; i < 100; ++i) points.emplace_back(std::cos(0.01 * i), std::sin(0.01 * i), 0.001 * (i % 10));
  test::expectInputError(
      [&] {
        rangeMapFromPointCloud(points, openvdb::math::Mat4d::identity(), AngularSteps{1e-5, 1e-5}, 0.01, "p.xyz", "p");
      },
      "p.xyz", "would bin the 100 points into up to ");
}

// A turn of columns of 1e-8 rad would be six hundred million.
TEST(BadPointCloud, StepsFinerThanAnyScannersAreRefused) {
  std::vector<Vec3d> points;
  for (int i = 0; i < 20; ++i) points.emplace_back(1.0, 1e-8 * (i % 5), 1e-8 * (i / 5));
  test::expectInputError(
      [&] {
        rangeMapFromPointCloud(points, openvdb::math::Mat4d::identity(), std::nullopt, 0.01, "p.xyz", "p");
      },
      "p.xyz", "are finer than any scanner's (at least 5.73e-05 degrees)");
}

TEST(BadPointCloud, PointsWhoseStepsCannotBeEstimatedAreNamed) {
  const std::vector<Vec3d> oneWay(50, Vec3d(1.0, 1.0, 1.0));
  test::expectInputError(
      [&] { rangeMapFromPointCloud(oneWay, openvdb::math::Mat4d::identity(), std::nullopt, 0.01, "p.xyz", "p"); },
      "p.xyz", "all the points lie in one direction from the scanner");
}

}  // namespace
}  // namespace levelfuse::io
