// E57 files: stations written in cartesian scaled integers or spherical
// floats land on the surface their scanner saw, wherever it stood; several
// scans in one file, scans without a grid, colours, multiple returns, and the
// ways in (loadScans, manifests). The real pump room (../shared/data/e57).

#include "support/E57Files.h"
#include "support/Files.h"
#include "support/PtxFiles.h"
#include "support/TestSupport.h"

#include <levelfuse/io/scans/E57Scans.h>
#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/Scans.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace levelfuse::io {
namespace {

using openvdb::Vec3d;
using test::E57ScanSpec;
using test::TempDir;

/// Cartesian points are stored to 0.1 mm.
constexpr double kStoredTo = 1e-4;

test::RangeAlong sphere() { return test::stationSphere(); }

std::vector<E57Scan> readAll(const std::string& path) {
  std::vector<E57Scan> scans;
  readE57Scans(path, [&](E57Scan&& scan) { scans.push_back(std::move(scan)); });
  return scans;
}

TEST(E57Scans, AStationInScaledIntegersIsReadOntoItsGridInTheScannersFrame) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  test::writeE57(dir.path("station.e57"), {test::stationScan(grid, sphere(), "hall")});
  const std::vector<E57Scan> scans = readAll(dir.path("station.e57"));
  ASSERT_EQ(scans.size(), 1u);
  const E57Scan& scan = scans[0];
  EXPECT_EQ(scan.index, 1);
  EXPECT_EQ(scan.name, "hall");
  EXPECT_TRUE(scan.structured());
  EXPECT_EQ(scan.station.columns, grid.columns);
  EXPECT_EQ(scan.station.rows, grid.rows);
  EXPECT_EQ(scan.records, static_cast<std::uint64_t>(grid.columns * grid.rows));
  EXPECT_EQ(scan.station.returns, scan.records);
  const std::vector<Vec3d> truth = test::scanPoints(grid, sphere());
  ASSERT_EQ(scan.station.points.size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i)
    ASSERT_LT((scan.station.points[i] - truth[i]).length(), kStoredTo) << "point " << i;
  EXPECT_FLOAT_EQ(scan.station.intensities[1], 1.0f);  // column 0, row 1: (0 * 7 + 1) % 2048
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(scan.station.scannerToWorld[i][j], grid.scannerToWorld[i][j], 1e-9);
}

TEST(E57Scans, AStationLandsOnTheSphereWhereverItsScannerStood) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  test::writeE57(dir.path("station.e57"), {test::stationScan(grid, sphere(), "hall")});
  const std::vector<RangeMap> maps = loadScans(dir.path("station.e57"));
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_EQ(maps[0].kind(), RangeMap::Kind::kSpherical);
  EXPECT_EQ(maps[0].name(), "hall");
  EXPECT_EQ(maps[0].validCount(), static_cast<std::size_t>(grid.columns * grid.rows));
  EXPECT_LT(test::farthestFromStationSphere(maps[0], grid.scannerToWorld), 2.0 * kStoredTo);
}

TEST(E57Scans, SphericalCoordinatesGiveTheSameStation) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  test::writeE57(dir.path("spherical.e57"), {test::sphericalStationScan(grid, sphere(), "")});
  const std::vector<E57Scan> scans = readAll(dir.path("spherical.e57"));
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_TRUE(scans[0].structured());
  EXPECT_TRUE(scans[0].station.intensities.size() == scans[0].station.points.size());
  const std::vector<Vec3d> truth = test::scanPoints(grid, sphere());
  for (std::size_t i = 0; i < truth.size(); ++i)
    ASSERT_LT((scans[0].station.points[i] - truth[i]).length(), 1e-9) << "point " << i;
  const std::vector<RangeMap> maps = loadScans(dir.path("spherical.e57"));
  EXPECT_EQ(maps[0].name(), "spherical scan 1");  // a scan without a name is named after the file
  EXPECT_LT(test::farthestFromStationSphere(maps[0], grid.scannerToWorld), 1e-6);
}

TEST(E57Scans, RaysWithoutAReturnStayEmpty) {
  TempDir dir;
  test::PtxGrid grid = test::turnedGrid();
  // A plane below the scanner: the rays above the horizon miss it.
  const test::RangeAlong floor = test::plane(Vec3d(0.0, 0.0, -1.0), 1.5);
  test::writeE57(dir.path("floor.e57"), {test::stationScan(grid, floor, "floor")});
  const std::vector<E57Scan> scans = readAll(dir.path("floor.e57"));
  std::size_t hits = 0;
  for (const Vec3d& p : test::scanPoints(grid, floor)) hits += p != Vec3d(0.0);
  ASSERT_GT(hits, 0u);
  ASSERT_LT(hits, static_cast<std::size_t>(grid.columns * grid.rows));
  EXPECT_EQ(scans[0].station.returns, hits);
}

TEST(E57Scans, SeveralScansOfOneFileEachKeepTheirPose) {
  TempDir dir;
  const test::PtxGrid first = test::turnedGrid();
  test::PtxGrid second = first;
  second.scannerToWorld = test::scannerLookingAt(Vec3d(-4.0, 1.0, 0.5), Vec3d(0.0, 0.0, 0.0));
  test::writeE57(dir.path("two.e57"),
                 {test::stationScan(first, sphere(), "one"), test::sphericalStationScan(second, sphere(), "two")});
  const std::vector<RangeMap> maps = loadScans(dir.path("two.e57"));
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps[1].name(), "two");
  EXPECT_LT(test::farthestFromStationSphere(maps[0], first.scannerToWorld), 2.0 * kStoredTo);
  EXPECT_LT(test::farthestFromStationSphere(maps[1], second.scannerToWorld), 1e-6);
}

TEST(E57Scans, ColoursAreCarriedToTheRangeMap) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  std::vector<Rgb8> colours(static_cast<std::size_t>(grid.columns * grid.rows), Rgb8{200, 100, 50});
  test::writeE57(dir.path("colour.e57"), {test::stationScan(grid, sphere(), "colour", colours)});
  const std::vector<E57Scan> scans = readAll(dir.path("colour.e57"));
  ASSERT_EQ(scans[0].station.colours.size(), colours.size());
  EXPECT_EQ(scans[0].station.colours[5][0], 200);
  EXPECT_EQ(scans[0].station.colours[5][1], 100);
  EXPECT_EQ(scans[0].station.colours[5][2], 50);
  EXPECT_TRUE(loadScans(dir.path("colour.e57"))[0].hasColours());
}

TEST(E57Scans, AScanWithoutIndicesIsBinnedByAngleAroundItsScanner) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  E57ScanSpec scan = test::stationScan(grid, sphere(), "cloud");
  scan.indexBounds.reset();
  scan.fields.erase(scan.fields.end() - 3, scan.fields.end() - 1);  // rowIndex and columnIndex
  test::writeE57(dir.path("cloud.e57"), {scan});
  const std::vector<E57Scan> scans = readAll(dir.path("cloud.e57"));
  EXPECT_FALSE(scans[0].structured());
  EXPECT_EQ(scans[0].station.points.size(), static_cast<std::size_t>(grid.columns * grid.rows));
  const std::vector<RangeMap> maps = loadScans(dir.path("cloud.e57"));
  EXPECT_GE(maps[0].validCount(), scans[0].station.points.size() * 9 / 10);
  EXPECT_LT(test::farthestFromStationSphere(maps[0], grid.scannerToWorld), 2.0 * kStoredTo);
}

TEST(E57Scans, OnlyTheFirstReturnOfARayIsKept) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  E57ScanSpec scan = test::stationScan(grid, sphere(), "returns");
  test::E57FieldSpec returnIndex;
  returnIndex.name = "returnIndex";
  returnIndex.type = "Integer";
  returnIndex.maximum = 1;
  returnIndex.values.assign(scan.fields[0].values.size(), 0.0);
  // A second return of the first ray, nearer: it is not the ray's first.
  for (test::E57FieldSpec& f : scan.fields) f.values.push_back(f.values[0]);
  for (int a = 0; a < 3; ++a) scan.fields[static_cast<std::size_t>(a)].values.back() *= 0.5;
  returnIndex.values.push_back(1.0);
  scan.fields.push_back(returnIndex);
  test::writeE57(dir.path("returns.e57"), {scan});
  const std::vector<E57Scan> scans = readAll(dir.path("returns.e57"));
  const std::vector<Vec3d> truth = test::scanPoints(grid, sphere());
  EXPECT_LT((scans[0].station.points[0] - truth[0]).length(), kStoredTo);
  EXPECT_EQ(scans[0].station.returns, truth.size());
}

TEST(E57Scans, ManifestEntriesReadE57FilesWithTheirSigma) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  test::writeE57(dir.path("station.e57"), {test::stationScan(grid, sphere(), "hall")});
  test::writeText(dir.path("scans.json"),
                  R"({"scans": [{"format": "e57", "file": "station.e57", "sigma": 0.004}]})");
  const std::vector<RangeMap> maps = loadScans(dir.path("scans.json"));
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_NEAR(maps[0].sigma(), 0.004, 1e-12);
  EXPECT_LT(test::farthestFromStationSphere(maps[0], grid.scannerToWorld), 2.0 * kStoredTo);
}

TEST(E57Scans, TakenScansAreHandedOverOneAtATime) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  test::writeE57(dir.path("two.e57"),
                 {test::stationScan(grid, sphere(), "one"), test::stationScan(grid, sphere(), "two")});
  ScanLoadOptions options;
  std::vector<std::string> taken;
  options.take = [&](RangeMap&& map) { taken.push_back(map.name()); };
  options.wanted = [](std::size_t i) { return i == 1; };
  EXPECT_TRUE(loadScans(dir.path("two.e57"), options).empty());
  EXPECT_EQ(taken, std::vector<std::string>{"two"});
}

// ---- the real pump room (../shared/data/e57) ----

TEST(E57RealFile, ThePumpRoomIsOneColouredStationOfItsWholeGrid) {
  const std::string path = test::sharedData("e57/pumpA.e57");
  if (path.empty()) GTEST_SKIP() << "../shared/data is absent: the real E57 scan is not tested";
  const std::vector<E57Scan> scans = readAll(path);
  ASSERT_EQ(scans.size(), 1u);
  const E57Scan& scan = scans[0];
  EXPECT_EQ(scan.name, "pumpA");
  EXPECT_EQ(scan.records, 155201u);
  EXPECT_EQ(scan.station.returns, 155201u);
  EXPECT_EQ(scan.station.rows, 1074);  // indexBounds: rows 0 to 1073
  EXPECT_EQ(scan.station.columns, 345);
  EXPECT_EQ(scan.station.colours.size(), scan.station.points.size());
  // Record 0 is row 267 of column 0 (as pye57 decodes it): x 0.7879..., within the cartesianBounds.
  const Vec3d first = scan.station.points[267];
  EXPECT_NEAR(std::atan2(first.y(), first.x()), -1.0810733, 1e-6);
  double nearest = 1e9, farthest = 0.0;
  for (const Vec3d& p : scan.station.points)
    if (p != Vec3d(0.0)) {
      nearest = std::min(nearest, p.length());
      farthest = std::max(farthest, p.length());
    }
  EXPECT_NEAR(nearest, 1.983619, 1e-5);   // the sphericalBounds' rangeMinimum
  EXPECT_NEAR(farthest, 5.429336, 1e-5);  // and rangeMaximum
  const std::vector<RangeMap> maps = loadScans(path);
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_TRUE(maps[0].hasColours());
  EXPECT_GE(maps[0].validCount(), 155201u * 99 / 100);  // a few returns share a pixel of the fitted grid
}

// ---- a file of another writer (tests/data/e57/cloudcompare, with its licence) ----

TEST(E57RealFile, CloudComparesSegmentOfThePumpRoomIsColouredPointsAroundTheScanner) {
  // Written by CloudCompare 2.12.4 with E57Format 2.3.0: single floats, no grid indices, no pose.
  const std::string path =
      (std::filesystem::path(LEVELFUSE_TEST_DATA_DIR) / "e57" / "cloudcompare" / "pipeSpherical.e57").string();
  const std::vector<E57Scan> scans = readAll(path);
  ASSERT_EQ(scans.size(), 1u);
  const E57Scan& scan = scans[0];
  EXPECT_EQ(scan.name, "pumpsA.segmented");
  EXPECT_EQ(scan.records, 1220u);
  EXPECT_FALSE(scan.structured());
  ASSERT_EQ(scan.station.points.size(), 1220u);
  EXPECT_EQ(scan.station.colours.size(), 1220u);
  EXPECT_EQ(scan.station.intensities.size(), 1220u);
  for (const Vec3d& p : scan.station.points) {  // within the scan's cartesianBounds
    EXPECT_TRUE(p.x() >= -1.2379294 && p.x() <= -0.3198701) << p;
    EXPECT_TRUE(p.y() >= -5.1274882 && p.y() <= -4.5700235) << p;
    EXPECT_TRUE(p.z() >= 1.4372075 && p.z() <= 1.8430030) << p;
  }
  const std::vector<RangeMap> maps = loadScans(path);
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_EQ(maps[0].kind(), RangeMap::Kind::kSpherical);
  EXPECT_TRUE(maps[0].hasColours());
  EXPECT_GE(maps[0].validCount(), 1220u * 97 / 100);  // binned by angle: a few share a pixel
}

}  // namespace
}  // namespace levelfuse::io
