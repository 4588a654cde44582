// Real PTX files, each copied into tests/data/ptx with its licence beside it:
//  - pdal/: PDAL's test files (github.com/PDAL/PDAL, test/data/ptx, as of its
//    commit 39d9163 of 2022-07-11; BSD);
//  - libptx/: libptx's test file (github.com/srajotte/libptx, test/data/points.ptx,
//    as of its commit 879e72b; MIT).

#include "support/InputErrors.h"
#include "support/TestSupport.h"

#include <levelfuse/io/scans/PtxScans.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace levelfuse::io {
namespace {

using openvdb::Vec3d;

/// The path of one of the real PTX files, in tests/data/ptx/<source>.
std::string realFile(const std::string& source, const std::string& name) {
  return (std::filesystem::path(LEVELFUSE_TEST_DATA_DIR) / "ptx" / source / name).string();
}

std::string pdalFile(const std::string& name) { return realFile("pdal", name); }

std::vector<PtxScan> readAll(const std::string& path) {
  std::vector<PtxScan> scans;
  readPtxScans(path, [&](PtxScan&& scan) { scans.push_back(std::move(scan)); });
  return scans;
}

/// The file's scan, which must be its only one (an empty scan if not).
PtxScan onlyScanOf(const std::string& path) {
  std::vector<PtxScan> scans = readAll(path);
  EXPECT_EQ(scans.size(), 1u) << path;
  return scans.size() == 1 ? std::move(scans[0]) : PtxScan();
}

void expectGrid(const PtxScan& scan, int columns, int rows, std::size_t returns) {
  EXPECT_EQ(scan.columns, columns);
  EXPECT_EQ(scan.rows, rows);
  EXPECT_EQ(scan.returns, returns);
}

// A scanner's own export: 2 columns x 6 rows in the scanner's frame, the
// transform its pose (a small tilt, written with six decimals), colour.
TEST(PdalPtxFiles, AScannersExportWithItsPose) {
  const std::string path = pdalFile("complex-transform.ptx");
  const PtxScan scan = onlyScanOf(path);
  expectGrid(scan, 2, 6, 4);
  ASSERT_EQ(scan.points.size(), 12u);
  EXPECT_EQ(scan.colours.size(), 12u);
  EXPECT_EQ(scan.colours[4], (PtxColour{33, 38, 24}));
  EXPECT_NEAR((scan.scannerToWorld.getTranslation() - Vec3d(-3.028748, -3.819741, -1.384333)).length(), 0.0, 1e-9);
  // The transform is the scanner's pose: the points come back as written.
  EXPECT_NEAR((scan.points[4] - Vec3d(-0.005630, 0.645218, -0.440506)).length(), 0.0, 1e-5);
  EXPECT_NEAR((scan.points[7] - Vec3d(-0.005600, 0.647598, -0.438828)).length(), 0.0, 1e-5);
  EXPECT_EQ(scan.points[0], Vec3d(0.0));
  // Its four returns stand on two columns' different rows: no two neighbours
  // along a row both have one, so no azimuth step can be told.
  test::expectInputError([&] { loadPtxScans(path); }, path, "scan 1 (lines 1 to 22): ");
}

// Points already in the world (UTM coordinates), the transform the identity:
// an airborne survey's points written 15 to a column, on no scanner's grid.
TEST(PdalPtxFiles, ARegisteredExportInTheWorld) {
  const std::string path = pdalFile("1.2-with-color.ptx");
  const PtxScan scan = onlyScanOf(path);
  expectGrid(scan, 15, 71, 1065);
  EXPECT_EQ(scan.colours.size(), 1065u);
  openvdb::BBoxd bounds;
  for (const Vec3d& p : scan.points) bounds.expand(p);
  EXPECT_NEAR(bounds.min().x(), 635619.85, 1e-6);
  EXPECT_NEAR(bounds.max().x(), 638982.55, 1e-6);
  EXPECT_NEAR(bounds.min().y(), 848899.70, 1e-6);
  EXPECT_NEAR(bounds.max().y(), 853535.43, 1e-6);
  EXPECT_NEAR(bounds.min().z(), 406.59, 1e-6);
  EXPECT_NEAR(bounds.max().z(), 586.38, 1e-6);
  test::expectInputError([&] { loadPtxScans(path); }, path,
                         "scan 1 (lines 1 to 1075): its 1065 returns fill only 81 pixels of its grid (6 x 26 of ");
}

// One row of 15 points without colour.
TEST(PdalPtxFiles, ARowWithoutColour) {
  const std::string path = pdalFile("no-color.ptx");
  const PtxScan scan = onlyScanOf(path);
  expectGrid(scan, 15, 1, 15);
  EXPECT_TRUE(scan.colours.empty());
}

// Two scans, the first with a transform (and scanner axis) that scales z by 2:
// not a rigid motion, refused at the scanner's axes, which come first.
TEST(PdalPtxFiles, AScaledTransformIsRefused) {
  const std::string path = pdalFile("multiple-and-transform.ptx");
  test::expectInputError([&] { readAll(path); }, path,
                         "line 6: the scanner's axes (lines 4 to 6) are not orthonormal (their dot products are off "
                         "by up to 3, more than 0.0001): not a rigid motion");
}

// Two registered scans of Cyclone's export, with colour: the ground beside a
// scanner 2.3 m above it, each scan with its own pose in the world. The
// first's 25 columns x 32 rows are one vertical sweep cut into columns: each
// column goes on down in elevation where the one before it stopped, at one
// azimuth (24.45 to 24.44 degrees). So its returns lie on no scanner's grid
// of that size, and the reader says so, naming the scan and its lines.
TEST(RealPtxFiles, OneSweepCutIntoColumnsIsNoGrid) {
  const std::string path = realFile("libptx", "points.ptx");
  const std::vector<PtxScan> scans = readAll(path);
  ASSERT_EQ(scans.size(), 2u);
  expectGrid(scans[0], 25, 32, 673);
  expectGrid(scans[1], 10, 9, 90);
  EXPECT_EQ(scans[0].colours.size(), 800u);
  EXPECT_EQ(scans[0].colours[0], (PtxColour{86, 104, 80}));
  EXPECT_NEAR((scans[0].scannerToWorld.getTranslation() - Vec3d(7.986539, -30.144609, 0.154285)).length(), 0.0, 1e-9);
  EXPECT_NEAR((scans[1].scannerToWorld.getTranslation() - Vec3d(-16.343402, -4.870179, 2.283744)).length(), 0.0, 1e-9);
  test::expectInputError([&] { loadPtxScans(path); }, path, "scan 1 (lines 1 to 810): its returns span up to ");
}

}  // namespace
}  // namespace levelfuse::io
