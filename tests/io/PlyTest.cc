// The strict PLY reader and the mesh writer.

#include "support/Files.h"
#include "support/InputErrors.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/Ply.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

namespace levelfuse::io {
namespace {

using test::TempDir;
using test::writeBytes;
using test::writeText;

const char* kHeader =
    "ply\n"
    "format ascii 1.0\n"
    "comment made by hand\n"
    "obj_info num_cols 2\n"
    "obj_info num_rows 2\n"
    "element vertex 3\n"
    "property float x\n"
    "property float y\n"
    "property float z\n"
    "element range_grid 4\n"
    "property list uchar int vertex_indices\n"
    "end_header\n";

/// Expects readPly(path) to throw an InputError naming the file whose message contains `fragment`.
void expectError(const std::string& path, const std::string& fragment) {
  test::expectInputError([&] { readPly(path); }, path, fragment);
}

TEST(Ply, ReadsAsciiWithListsAndMetadata) {
  TempDir dir;
  writeText(dir.path("a.ply"), std::string(kHeader) + "0 0 0\n1.5 -2 3e-3\n  4 5 6  \n1 0\n0\n1 2\n1 1\n");
  const PlyData ply = readPly(dir.path("a.ply"));
  EXPECT_EQ(ply.format, PlyFormat::kAscii);
  EXPECT_EQ(ply.info("num_cols"), "2");
  ASSERT_EQ(ply.comments.size(), 1u);
  const PlyElement* v = ply.element("vertex");
  ASSERT_TRUE(v);
  EXPECT_EQ(v->count, 3u);
  EXPECT_DOUBLE_EQ(v->values[v->property("y")][1], -2.0);
  EXPECT_DOUBLE_EQ(v->values[v->property("z")][1], 3e-3);
  const PlyElement* g = ply.element("range_grid");
  ASSERT_TRUE(g);
  const auto& offsets = g->listOffsets[0];
  ASSERT_EQ(offsets.size(), 5u);
  EXPECT_EQ(offsets[2] - offsets[1], 0u);  // an empty cell
  EXPECT_DOUBLE_EQ(g->values[0][offsets[2]], 2.0);
  EXPECT_TRUE(ply.warnings.empty());
}

TEST(Ply, ToleratesUnknownHeaderLinesWithAWarning) {
  TempDir dir;
  writeText(dir.path("a.ply"),
            "ply\nformat ascii 1.0\nscanner_mode fast\nelement vertex 1\nproperty float x\nend_header\n7\n");
  const PlyData ply = readPly(dir.path("a.ply"));
  ASSERT_EQ(ply.warnings.size(), 1u);
  EXPECT_NE(ply.warnings[0].find("scanner_mode"), std::string::npos);
  EXPECT_DOUBLE_EQ(ply.element("vertex")->values[0][0], 7.0);
}

std::vector<unsigned char> binaryFile(bool littleEndian) {
  const std::string header = std::string("ply\nformat ") + (littleEndian ? "binary_little_endian" : "binary_big_endian") +
                             " 1.0\nelement vertex 2\nproperty float x\nproperty double y\nproperty short z\n"
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  std::vector<unsigned char> bytes(header.begin(), header.end());
  const auto put = [&](const void* p, std::size_t n) {
    const unsigned char* b = static_cast<const unsigned char*>(p);
    std::vector<unsigned char> v(b, b + n);
    if (!littleEndian) std::reverse(v.begin(), v.end());
    bytes.insert(bytes.end(), v.begin(), v.end());
  };
  for (int i = 0; i < 2; ++i) {
    const float x = 1.25f + i;
    const double y = -2.5 - i;
    const std::int16_t z = static_cast<std::int16_t>(-300 + i);
    put(&x, 4);
    put(&y, 8);
    put(&z, 2);
  }
  const unsigned char three = 3;
  bytes.push_back(three);
  for (std::int32_t i : {0, 1, 1}) put(&i, 4);
  return bytes;
}

TEST(Ply, ReadsBinaryOfBothEndiannesses) {
  TempDir dir;
  for (bool little : {true, false}) {
    const std::string path = dir.path(little ? "le.ply" : "be.ply");
    writeBytes(path, binaryFile(little));
    const PlyData ply = readPly(path);
    const PlyElement* v = ply.element("vertex");
    ASSERT_TRUE(v);
    EXPECT_DOUBLE_EQ(v->values[0][1], 2.25);
    EXPECT_DOUBLE_EQ(v->values[1][0], -2.5);
    EXPECT_DOUBLE_EQ(v->values[2][1], -299.0);
    const PlyElement* f = ply.element("face");
    ASSERT_EQ(f->listOffsets[0].back(), 3u);
    EXPECT_DOUBLE_EQ(f->values[0][2], 1.0);
  }
}

TEST(Ply, RejectsBrokenFilesWithClearErrors) {
  TempDir dir;
  const auto file = [&](const std::string& name, const std::string& text) {
    writeText(dir.path(name), text);
    return dir.path(name);
  };
  expectError(dir.path("missing.ply"), "no such file");
  expectError(file("empty.ply", ""), "no end_header");
  expectError(file("notply.ply", "solid cube\nfacet normal 0 0 1\n"), "not a PLY file");
  expectError(file("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"), "no end_header");
  expectError(file("format.ply", "ply\nformat utf8 1.0\nend_header\n"), "unknown format 'utf8'");
  expectError(file("noformat.ply", "ply\nelement vertex 0\nend_header\n"), "no format line");
  expectError(file("count.ply", "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n"), "invalid count '-3'");
  expectError(file("orphan.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n"),
              "a property before any element");
  expectError(file("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n1\n"),
              "unknown type 'quad'");
  // Counts that disagree with the data. Long numbers keep these files past the
  // size check, so the parser itself meets the problem.
  const std::string one = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                          "property float z\nend_header\n";
  expectError(file("short.ply", one + "0.000000000 0.000000000 0.000000000\n"), "ends in 'vertex' entry 1 of 2");
  expectError(file("fewer.ply", one + "0.000000000 0.000000000\n1.000000000 1.0000000 1.0000000\n"),
              "line 8: 'vertex' entry 0 has fewer values than its 3 properties");
  expectError(file("more.ply", one + "0.0 0.0 0.0 9.0\n1 1 1\n"), "more values than its 3 properties");
  expectError(file("extra.ply", one + "0 0 0\n1 1 1\n5 5 5\n"), "data after the last declared element");
  expectError(file("word.ply", one + "0 zero 0\n1 1 1\n"), "'zero' is not a number");
  expectError(file("byte.ply", std::string(kHeader) + "0 0 0\n1 1 1\n2 2 2\n300 1\n0\n0\n0\n"),
              "does not fit the integer type");
  expectError(file("fraction.ply", std::string(kHeader) + "0 0 0\n1 1 1\n2 2 2\n1.5 1\n0\n0\n0\n"), "does not fit");
  expectError(file("small.ply", std::string(kHeader) + "0 0 0\n"), "only 6 bytes follow the header");
  // Absurd sizes are refused before anything is allocated.
  expectError(file("huge.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
                               "property float x\nend_header\n\x01\x02"),
              "declares 1000000000000 entries, but only 2 bytes follow");
  std::vector<unsigned char> truncated = binaryFile(true);
  truncated.resize(truncated.size() - 5);
  writeBytes(dir.path("truncated.ply"), truncated);
  expectError(dir.path("truncated.ply"), "truncated");
  std::vector<unsigned char> garbage(4096);
  for (std::size_t i = 0; i < garbage.size(); ++i) garbage[i] = static_cast<unsigned char>((i * 2654435761u) >> 13);
  writeBytes(dir.path("garbage.ply"), garbage);
  expectError(dir.path("garbage.ply"), "not a PLY file");
}

TEST(Ply, RefusesFilesBeyondTheMemoryBudget) {
  TempDir dir;
  const std::string path = dir.path("a.ply");
  writeText(path, std::string(kHeader) + "0 0 0\n1.5 -2 3e-3\n4 5 6\n1 0\n0\n1 2\n1 1\n");
  const auto bytes = std::filesystem::file_size(path);
  test::expectInputError([&] { readPly(path, MemoryBudget(bytes - 1)); }, path,
                         "reading the file needs about " + std::to_string(bytes) + " bytes of memory, more than the " +
                             std::to_string(bytes - 1) + " bytes levelfuse may use: split the scan into smaller files");
  // The file fits, its values as doubles do not.
  test::expectInputError([&] { readPly(path, MemoryBudget(bytes + 100)); }, path, "reading its values needs about");
  EXPECT_EQ(readPly(path).element("vertex")->count, 3u);
}

TEST(Ply, MeshesRoundTrip) {
  TempDir dir;
  const std::vector<float> xyz{0, 0, 0, 1, 0, 0, 0, 1, 0.5f};
  const std::vector<std::uint32_t> tri{0, 1, 2};
  for (bool binary : {true, false}) {
    const std::string path = dir.path(binary ? "b.ply" : "a.ply");
    writeMeshPly(path, xyz, tri, binary);
    const PlyData ply = readPly(path);
    EXPECT_EQ(ply.format, binary ? PlyFormat::kBinaryLittleEndian : PlyFormat::kAscii);
    EXPECT_DOUBLE_EQ(ply.element("vertex")->values[2][2], 0.5);
    EXPECT_DOUBLE_EQ(ply.element("face")->values[0][1], 1.0);
  }
  const std::vector<std::uint8_t> rgb{255, 0, 0, 0, 128, 0, 1, 2, 3};
  for (bool binary : {true, false}) {
    const std::string path = dir.path(binary ? "cb.ply" : "ca.ply");
    writeMeshPly(path, xyz, tri, binary, rgb);
    const PlyData ply = readPly(path);
    const PlyElement& vertex = *ply.element("vertex");
    ASSERT_GE(vertex.property("red"), 0);
    EXPECT_EQ(vertex.properties[vertex.property("red")].type, PlyType::kUInt8);
    EXPECT_DOUBLE_EQ(vertex.values[vertex.property("z")][2], 0.5);
    EXPECT_DOUBLE_EQ(vertex.values[vertex.property("green")][1], 128.0);
    EXPECT_DOUBLE_EQ(vertex.values[vertex.property("blue")][2], 3.0);
    EXPECT_DOUBLE_EQ(ply.element("face")->values[0][2], 2.0);
  }
  EXPECT_THROW(writeMeshPly(dir.path("short.ply"), xyz, tri, true, {1, 2, 3}), std::invalid_argument);
  EXPECT_THROW(writeMeshPly(dir.path("missing/dir/x.ply"), xyz, tri), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir.path("missing")));
}

}  // namespace
}  // namespace levelfuse::io
