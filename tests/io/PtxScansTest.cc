// PTX files: scans of a sphere and a floor seen from a turned scanner land on
// them, whether the points are written in the scanner's frame or the world's;
// several scans in one file, colours, and the ways in (loadScans, manifests).

#include "support/Files.h"
#include "support/PtxFiles.h"

#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/PtxScans.h>
#include <levelfuse/io/scans/Scans.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace levelfuse::io {
namespace {

using openvdb::Vec3d;
using openvdb::math::Mat4d;
using test::PtxFrame;
using test::TempDir;
using test::writeText;

/// The floor 1.5 m below the scanner (scanner frame: z = -1.5), seen by the rows below the horizon.
const Vec3d kFloorNormal(0.0, 0.0, -1.0);
constexpr double kFloorOffset = 1.5;

std::vector<Vec3d> spherePoints(const test::PtxGrid& grid) {
  return test::scanPoints(grid, test::stationSphere());
}

std::vector<Vec3d> floorPoints(const test::PtxGrid& grid) {
  return test::scanPoints(grid, test::plane(kFloorNormal, kFloorOffset));
}

std::size_t returnsOf(const std::vector<Vec3d>& points) {
  std::size_t returns = 0;
  for (const Vec3d& p : points) returns += p != Vec3d(0.0);
  return returns;
}

/// The largest `distance` of a map's readings (world points) from a surface.
double farthestReading(const RangeMap& map, const std::function<double(const Vec3d&)>& distance) {
  double farthest = 0.0;
  for (int v = 0; v < map.height(); ++v)
    for (int u = 0; u < map.width(); ++u)
      if (map.valid(u, v)) farthest = std::max(farthest, std::fabs(distance(map.readingPoint(u, v))));
  return farthest;
}

double farthestFromFloor(const RangeMap& map, const Mat4d& scannerToWorld) {
  const Vec3d normal = scannerToWorld.transform3x3(kFloorNormal);
  const double offset = kFloorOffset + normal.dot(scannerToWorld.getTranslation());
  return farthestReading(map, [&](const Vec3d& p) { return normal.dot(p) - offset; });
}

void expectSameMatrix(const Mat4d& a, const Mat4d& b, double tolerance) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(a(i, j), b(i, j), tolerance) << "(" << i << ", " << j << ")";
}

/// Readings within a ten-thousandth of a millimetre of the surface: the
/// points are written with nine decimals and read back pixel for pixel.
constexpr double kOnTheSurface = 1e-7 * 10.0;

TEST(PtxScans, ASphereAroundATurnedScannerLandsOnTheSphere) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = spherePoints(grid);
  writeText(dir.path("sphere.ptx"), test::ptxScanText(grid, points, PtxFrame::kScanner));
  const std::vector<RangeMap> maps = loadScans(dir.path("sphere.ptx"));
  ASSERT_EQ(maps.size(), 1u);
  const RangeMap& map = maps[0];
  EXPECT_EQ(map.kind(), RangeMap::Kind::kSpherical);
  EXPECT_EQ(map.name(), "sphere scan 1");
  EXPECT_EQ(map.validCount(), returnsOf(points));
  EXPECT_EQ(map.validCount(), static_cast<std::size_t>(grid.columns * grid.rows));
  EXPECT_DOUBLE_EQ(map.sigma(), 0.002);
  expectSameMatrix(map.mapToWorld(), grid.scannerToWorld, 1e-9);
  EXPECT_LT(test::farthestFromStationSphere(map, grid.scannerToWorld), kOnTheSurface);
}

TEST(PtxScans, AnAzimuthStepThatDoesNotDivideTheTurnLandsOnTheSphereToo) {
  TempDir dir;
  test::PtxGrid grid = test::turnedGrid();
  grid.azimuthStep = 0.05;  // 125.7 a turn; the scan crosses azimuth 0
  const std::vector<Vec3d> points = spherePoints(grid);
  writeText(dir.path("sphere.ptx"), test::ptxScanText(grid, points, PtxFrame::kScanner));
  const RangeMap map = loadScans(dir.path("sphere.ptx")).at(0);
  EXPECT_EQ(map.validCount(), returnsOf(points));
  EXPECT_LT(test::farthestFromStationSphere(map, grid.scannerToWorld), kOnTheSurface);
}

TEST(PtxScans, AFloorSeenBelowTheHorizonLandsOnTheFloor) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = floorPoints(grid);
  ASSERT_EQ(returnsOf(points), static_cast<std::size_t>(grid.columns * 8));  // the rows below the horizon
  writeText(dir.path("floor.ptx"), test::ptxScanText(grid, points, PtxFrame::kScanner));
  const RangeMap map = loadScans(dir.path("floor.ptx")).at(0);
  EXPECT_EQ(map.kind(), RangeMap::Kind::kSpherical);
  EXPECT_EQ(map.validCount(), returnsOf(points));
  EXPECT_LT(farthestFromFloor(map, grid.scannerToWorld), kOnTheSurface * 30.0);  // readings up to 30 m away
}

TEST(PtxScans, PointsWrittenInTheWorldOrInTheScannersFrameGiveTheSameMap) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = spherePoints(grid);
  writeText(dir.path("local.ptx"), test::ptxScanText(grid, points, PtxFrame::kScanner));
  writeText(dir.path("world.ptx"), test::ptxScanText(grid, points, PtxFrame::kWorld));
  const RangeMap local = loadScans(dir.path("local.ptx")).at(0);
  const RangeMap world = loadScans(dir.path("world.ptx")).at(0);
  ASSERT_EQ(world.width(), local.width());
  ASSERT_EQ(world.height(), local.height());
  EXPECT_EQ(world.validCount(), local.validCount());
  expectSameMatrix(world.mapToWorld(), local.mapToWorld(), 1e-9);
  EXPECT_NEAR(world.sphericalProjection().azimuthStart, local.sphericalProjection().azimuthStart, 1e-7);
  EXPECT_NEAR(world.sphericalProjection().azimuthStep, local.sphericalProjection().azimuthStep, 1e-7);
  EXPECT_NEAR(world.sphericalProjection().elevationStart, local.sphericalProjection().elevationStart, 1e-7);
  EXPECT_NEAR(world.sphericalProjection().elevationStep, local.sphericalProjection().elevationStep, 1e-7);
  for (int v = 0; v < local.height(); ++v)
    for (int u = 0; u < local.width(); ++u) {
      ASSERT_EQ(world.valid(u, v), local.valid(u, v)) << u << ", " << v;
      if (local.valid(u, v)) {
        EXPECT_NEAR(world.reading(u, v), local.reading(u, v), 1e-5) << u << ", " << v;
      }
    }
  EXPECT_LT(test::farthestFromStationSphere(world, grid.scannerToWorld), kOnTheSurface);
}

TEST(PtxScans, ThePointsAreReadIntoTheScannersFrame) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = floorPoints(grid);
  writeText(dir.path("world.ptx"), test::ptxScanText(grid, points, PtxFrame::kWorld));
  std::vector<PtxScan> scans;
  readPtxScans(dir.path("world.ptx"), [&](PtxScan&& scan) { scans.push_back(std::move(scan)); });
  ASSERT_EQ(scans.size(), 1u);
  const PtxScan& scan = scans[0];
  EXPECT_EQ(scan.index, 1);
  EXPECT_EQ(scan.columns, grid.columns);
  EXPECT_EQ(scan.rows, grid.rows);
  EXPECT_EQ(scan.firstLine, 1);
  EXPECT_EQ(scan.lastLine, 10 + grid.columns * grid.rows);
  EXPECT_EQ(scan.returns, returnsOf(points));
  expectSameMatrix(scan.scannerToWorld, grid.scannerToWorld, 1e-9);
  ASSERT_EQ(scan.points.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_LT((scan.points[i] - points[i]).length(), 1e-7) << "point " << i;  // misses stay at the origin
  EXPECT_EQ(scan.intensities, std::vector<float>(points.size(), 0.5f));
  EXPECT_TRUE(scan.colours.empty());
}

TEST(PtxScans, SevenFieldLinesAreReadWithTheirColours) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = spherePoints(grid);
  writeText(dir.path("grey.ptx"), test::ptxScanText(grid, points, PtxFrame::kScanner));
  writeText(dir.path("colour.ptx"), test::ptxScanText(grid, points, PtxFrame::kScanner, /*colours=*/true));
  std::vector<PtxColour> colours;
  readPtxScans(dir.path("colour.ptx"), [&](PtxScan&& scan) { colours = scan.colours; });
  ASSERT_EQ(colours.size(), points.size());
  for (std::size_t i = 0; i < colours.size(); ++i) {
    const PtxColour expected{static_cast<std::uint8_t>(i * 7 % 256), static_cast<std::uint8_t>(i * 11 % 256), 200};
    EXPECT_EQ(colours[i], expected) << "point " << i;
  }
  // The map is the grey scan's, and each pixel has its point's colour (the
  // grid comes back pixel for pixel: pixel (u, v) is column u's point v).
  const RangeMap grey = loadScans(dir.path("grey.ptx")).at(0);
  const RangeMap colour = loadScans(dir.path("colour.ptx")).at(0);
  EXPECT_FALSE(grey.hasColours());
  ASSERT_TRUE(colour.hasColours());
  ASSERT_EQ(colour.width(), grey.width());
  ASSERT_EQ(colour.height(), grey.height());
  ASSERT_EQ(colour.width(), grid.columns);
  for (int v = 0; v < grey.height(); ++v)
    for (int u = 0; u < grey.width(); ++u)
      if (grey.valid(u, v)) {
        EXPECT_EQ(colour.reading(u, v), grey.reading(u, v)) << u << ", " << v;
        const std::size_t point = static_cast<std::size_t>(u) * grid.rows + v;
        EXPECT_EQ(colour.colours()[static_cast<std::size_t>(v) * colour.width() + u], colours[point]) << u << ", " << v;
      }
}

TEST(PtxScans, TwoScansInOneFileAreHandedOverOneAtATime) {
  TempDir dir;
  const test::PtxGrid turned = test::turnedGrid();
  test::PtxGrid upright;
  upright.scannerToWorld.setTranslation(Vec3d(-2.0, 0.5, 1.0));
  writeText(dir.path("two.ptx"), test::ptxScanText(turned, spherePoints(turned), PtxFrame::kScanner) +
                                     test::ptxScanText(upright, floorPoints(upright), PtxFrame::kWorld) + "\n\n");
  ScanLoadOptions options;
  std::vector<RangeMap> taken;
  std::vector<std::pair<std::size_t, std::size_t>> progress;
  options.take = [&](RangeMap&& map) { taken.push_back(std::move(map)); };
  options.progress = [&](std::size_t read, std::size_t total) { progress.emplace_back(read, total); };
  EXPECT_TRUE(loadScans(dir.path("two.ptx"), options).empty());
  ASSERT_EQ(taken.size(), 2u);
  EXPECT_EQ(taken[0].name(), "two scan 1");
  EXPECT_EQ(taken[1].name(), "two scan 2");
  EXPECT_LT(test::farthestFromStationSphere(taken[0], turned.scannerToWorld), kOnTheSurface);
  EXPECT_LT(farthestFromFloor(taken[1], upright.scannerToWorld), kOnTheSurface * 30.0);
  EXPECT_EQ(progress, (std::vector<std::pair<std::size_t, std::size_t>>{{1, 1}, {2, 2}}));
  EXPECT_EQ(loadScans(dir.path("two.ptx")).size(), 2u);  // without a taker, both returned
}

TEST(PtxScans, WindowsLineBreaksBlankLinesAtTheEndAndAnUppercaseExtension) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  std::string text;
  for (const char c : test::ptxScanText(grid, spherePoints(grid), PtxFrame::kScanner))
    text += c == '\n' ? std::string("\r\n") : std::string(1, c);
  writeText(dir.path("SPHERE.PTX"), text + "\r\n  \n\t\n");
  const RangeMap map = loadScans(dir.path("SPHERE.PTX")).at(0);
  EXPECT_EQ(map.validCount(), static_cast<std::size_t>(grid.columns * grid.rows));
  EXPECT_LT(test::farthestFromStationSphere(map, grid.scannerToWorld), kOnTheSurface);
}

TEST(PtxScans, TheNoiseIsTheOptionsOrTheManifestEntrys) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  writeText(dir.path("sphere.ptx"), test::ptxScanText(grid, spherePoints(grid), PtxFrame::kScanner));
  ScanLoadOptions options;
  options.setSigma(0.01);
  EXPECT_DOUBLE_EQ(loadScans(dir.path("sphere.ptx"), options).at(0).sigma(), 0.01);
  writeText(dir.path("scans.json"), R"({"scans": [
      {"format": "ptx", "file": "sphere.ptx", "sigma": 0.004},
      {"format": "ptx", "file": "sphere.ptx"} ]})");
  const std::vector<RangeMap> maps = loadManifest(dir.path("scans.json"));
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_DOUBLE_EQ(maps[0].sigma(), 0.004);
  EXPECT_DOUBLE_EQ(maps[1].sigma(), 0.002);
  EXPECT_EQ(maps[0].name(), "sphere scan 1");
  EXPECT_LT(test::farthestFromStationSphere(maps[0], grid.scannerToWorld), kOnTheSurface);
  EXPECT_DOUBLE_EQ(loadManifest(dir.path("scans.json"), options).at(1).sigma(), 0.01);
}

}  // namespace
}  // namespace levelfuse::io
