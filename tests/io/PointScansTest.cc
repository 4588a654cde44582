// Point clouds with their sensor's pose: a sphere seen by a turned scanner,
// written as XYZ, PLY (ASCII and binary) and KITTI sweeps, read through
// manifests into spherical range maps that land on the sphere; KITTI
// odometry's poses composed by hand; colours and fields as the files give them.

#include "support/Files.h"
#include "support/PointFiles.h"
#include "support/PtxFiles.h"

#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/PointScans.h>
#include <levelfuse/io/scans/Scans.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace levelfuse::io {
namespace {

using openvdb::Vec3d;
using openvdb::math::Mat4d;
using test::TempDir;
using test::writeText;

/// The grid's returns on the sphere, in the scanner's frame.
std::vector<Vec3d> sensorPoints(const test::PtxGrid& grid) {
  std::vector<Vec3d> points;
  for (const Vec3d& p : test::scanPoints(grid, test::stationSphere()))
    if (p != Vec3d(0.0)) points.push_back(p);
  return points;
}

std::vector<Vec3d> inWorld(const std::vector<Vec3d>& points, const Mat4d& sensorToWorld) {
  std::vector<Vec3d> world;
  for (const Vec3d& p : points) world.push_back(sensorToWorld.transform(p));
  return world;
}

void expectSameMatrix(const Mat4d& a, const Mat4d& b, double tolerance) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(a(i, j), b(i, j), tolerance) << "(" << i << ", " << j << ")";
}

/// A map with the grid's steps, every point on a pixel of its own, on the sphere.
void expectTheSphere(const RangeMap& map, const test::PtxGrid& grid, std::size_t points, double tolerance) {
  EXPECT_EQ(map.kind(), RangeMap::Kind::kSpherical);
  EXPECT_EQ(map.validCount(), points);
  EXPECT_NEAR(std::fabs(map.sphericalProjection().azimuthStep), grid.azimuthStep, 1e-6);
  EXPECT_NEAR(std::fabs(map.sphericalProjection().elevationStep), grid.elevationStep, 1e-6);
  EXPECT_LT(test::farthestFromStationSphere(map, grid.scannerToWorld), tolerance);
}

/// Double-precision text: the readings within a micrometre of the sphere.
constexpr double kTextPrecision = 1e-6;
/// float32 coordinates of points 5 m away: within ten micrometres.
constexpr double kFloatPrecision = 1e-5;

TEST(PointScans, XyzPointsInTheWorldWithTheSensorsPose) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = sensorPoints(grid);
  writeText(dir.path("sphere.xyz"), test::xyzText(inWorld(points, grid.scannerToWorld), test::someColours(points.size())));
  writeText(dir.path("scans.json"), R"({"scans": [{"format": "points", "file": "sphere.xyz", "pose": )" +
                                        test::manifestPose(grid.scannerToWorld) + "}]}");
  const std::vector<RangeMap> maps = loadScans(dir.path("scans.json"));
  ASSERT_EQ(maps.size(), 1u);
  expectTheSphere(maps[0], grid, points.size(), kTextPrecision);
  expectSameMatrix(maps[0].mapToWorld(), grid.scannerToWorld, 1e-9);
  EXPECT_EQ(maps[0].name(), "sphere.xyz");
  EXPECT_DOUBLE_EQ(maps[0].sigma(), 0.002);
}

// With only its origin, the sensor's axes are the world's: the same points,
// other azimuths, the same sphere.
TEST(PointScans, XyzPointsWithTheSensorsOrigin) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = sensorPoints(grid);
  writeText(dir.path("sphere.xyz"), test::xyzText(inWorld(points, grid.scannerToWorld)));
  writeText(dir.path("scans.json"), R"({"scans": [{"format": "points", "file": "sphere.xyz", "origin": [1, 2, 3]}]})");
  const RangeMap map = loadManifest(dir.path("scans.json")).at(0);
  expectTheSphere(map, grid, points.size(), kTextPrecision);
  Mat4d atTheOrigin = Mat4d::identity();
  atTheOrigin.setTranslation(Vec3d(1.0, 2.0, 3.0));
  expectSameMatrix(map.mapToWorld(), atTheOrigin, 1e-12);
}

TEST(PointScans, PlyAsciiAndBinaryAndSensorCoordinatesGiveTheXyzFilesMap) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = sensorPoints(grid), world = inWorld(points, grid.scannerToWorld);
  const std::vector<Rgb8> colours = test::someColours(points.size());
  writeText(dir.path("sphere.xyz"), test::xyzText(world));
  writeText(dir.path("ascii.ply"), test::plyPoints(world, colours, false));
  writeText(dir.path("binary.ply"), test::plyPoints(world, colours, true));
  writeText(dir.path("sensor.xyz"), test::xyzText(points));
  const std::string pose = test::manifestPose(grid.scannerToWorld);
  writeText(dir.path("scans.json"),
            R"({"scans": [{"format": "points", "file": "sphere.xyz", "pose": )" + pose + R"(},
                {"format": "points", "file": "ascii.ply", "pose": )" + pose + R"(},
                {"format": "points", "file": "binary.ply", "pose": )" + pose + R"(},
                {"format": "points", "file": "sensor.xyz", "coordinates": "sensor", "pose": )" + pose + "}]}");
  const std::vector<RangeMap> maps = loadManifest(dir.path("scans.json"));
  ASSERT_EQ(maps.size(), 4u);
  for (std::size_t m = 1; m < maps.size(); ++m) {
    SCOPED_TRACE(maps[m].name());
    expectTheSphere(maps[m], grid, points.size(), kTextPrecision);
    ASSERT_EQ(maps[m].width(), maps[0].width());
    ASSERT_EQ(maps[m].height(), maps[0].height());
    for (int v = 0; v < maps[0].height(); ++v)
      for (int u = 0; u < maps[0].width(); ++u) {
        ASSERT_EQ(maps[m].valid(u, v), maps[0].valid(u, v)) << u << ", " << v;
        if (maps[0].valid(u, v)) {
          EXPECT_NEAR(maps[m].reading(u, v), maps[0].reading(u, v), 1e-5);
        }
      }
  }
}

TEST(PointScans, GivenStepsAreTheMapsSteps) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = sensorPoints(grid);
  writeText(dir.path("sphere.xyz"), test::xyzText(inWorld(points, grid.scannerToWorld)));
  const double degrees = 180.0 / M_PI;
  writeText(dir.path("scans.json"), R"({"scans": [{"format": "points", "file": "sphere.xyz", "origin": [1, 2, 3],
      "azimuth_step": )" + std::to_string(grid.azimuthStep * degrees * 0.5) +
                                        R"(, "elevation_step": )" + std::to_string(grid.elevationStep * degrees) +
                                        R"(, "sigma": 0.004}]})");
  const RangeMap map = loadManifest(dir.path("scans.json")).at(0);
  EXPECT_NEAR(std::fabs(map.sphericalProjection().azimuthStep), grid.azimuthStep * 0.5, 1e-6);
  EXPECT_DOUBLE_EQ(map.sigma(), 0.004);
  EXPECT_EQ(map.validCount(), points.size());  // half steps: each point on a pixel of its own, one pixel in two
}

TEST(PointScans, GivenRowElevationsAreTheMapsRows) {
  // A sensor's lasers, a degree apart below the horizon and half a degree
  // above, each sweeping 90 degrees of a wall 5 m away in degree steps.
  const std::vector<double> lasers{-4.0, -3.0, -2.0, -1.0, -0.5, 0.0, 0.5, 1.0};
  std::vector<Vec3d> points;
  for (const double elevation : lasers)
    for (int c = 0; c <= 90; ++c) {
      const double e = elevation * M_PI / 180.0, a = (c - 45) * M_PI / 180.0;
      points.push_back(Vec3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)) * 5.0);
    }
  TempDir dir;
  writeText(dir.path("sweep.xyz"), test::xyzText(points));
  writeText(dir.path("scans.json"), R"({"scans": [{"format": "points", "file": "sweep.xyz", "origin": [0, 0, 0],
      "azimuth_step": 1, "row_elevations": [-4, -3, -2, -1, -0.5, 0, 0.5, 1]}]})");
  const RangeMap map = loadManifest(dir.path("scans.json")).at(0);
  ASSERT_EQ(map.height(), 8);
  EXPECT_EQ(map.width(), 91);
  EXPECT_EQ(map.validCount(), points.size());  // each laser's points in its own row
  const std::vector<double>& rows = map.sphericalProjection().rowElevations;
  ASSERT_EQ(rows.size(), lasers.size());
  for (std::size_t r = 0; r < rows.size(); ++r) EXPECT_NEAR(rows[r], lasers[r] * M_PI / 180.0, 1e-12) << r;
}

TEST(PointScans, KittiSweepWithAPoseLandsOnTheSphereToFloatPrecision) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = sensorPoints(grid);
  test::writeBytes(dir.path("000000.bin"), test::kittiBinBytes(points));
  const PointCloud cloud = readKittiBin(dir.path("000000.bin"));
  ASSERT_EQ(cloud.points.size(), points.size());
  EXPECT_TRUE(cloud.colours.empty());
  for (std::size_t i = 0; i < points.size(); ++i)  // float32: within half a unit in the last place
    EXPECT_LT((cloud.points[i] - points[i]).length(), 1e-6) << "point " << i;
  writeText(dir.path("scans.json"), R"({"scans": [{"format": "kitti-bin", "file": "000000.bin", "pose": )" +
                                        test::manifestPose(grid.scannerToWorld) + "}]}");
  const RangeMap map = loadManifest(dir.path("scans.json")).at(0);
  expectTheSphere(map, grid, points.size(), kFloatPrecision);
  EXPECT_EQ(map.name(), "000000.bin");
}

/// Velodyne to camera as KITTI's Tr is (camera x = -velodyne y, y = -z, z =
/// x), moved by (0.1, -0.2, 0.3); row-vector layout.
Mat4d kittiTr() {
  return Mat4d(0.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.1, -0.2, 0.3, 1.0);
}

/// Camera 0 to the world: turned 30 degrees about the camera's y axis, moved by (5, 1, -2); row-vector layout.
Mat4d kittiPose() {
  const double c = std::cos(M_PI / 6.0), s = std::sin(M_PI / 6.0);
  return Mat4d(c, 0.0, -s, 0.0, 0.0, 1.0, 0.0, 0.0, s, 0.0, c, 0.0, 5.0, 1.0, -2.0, 1.0);
}

std::string kittiCalib(const Mat4d& tr) {
  const std::string projection = "P0: 7.188560000000e+02 0 6.071928000000e+02 0 0 7.188560000000e+02 "
                                 "1.852157000000e+02 0 0 0 1 0\n";
  return projection + "P1: 7.188560000000e+02 0 6.071928000000e+02 -3.861448000000e+02 0 7.188560000000e+02 "
                      "1.852157000000e+02 0 0 0 1 0\nTr: " + test::kittiTransformText(tr) + "\n";
}

TEST(PointScans, KittiOdometryComposesTheFramesPoseWithTr) {
  TempDir dir;
  writeText(dir.path("calib.txt"), kittiCalib(kittiTr()));
  writeText(dir.path("00.txt"), test::kittiTransformText(Mat4d::identity()) + "\n" +
                                    test::kittiTransformText(kittiPose()) + "\n");
  const Mat4d velodyneToWorld = kittiVelodyneToWorld(readKittiCameraToWorld(dir.path("00.txt"), 1),
                                                     readKittiVelodyneToCamera(dir.path("calib.txt")));
  // By hand, column vectors: camera = Tr p, world = pose camera.
  const Vec3d p(1.0, 2.0, 3.0);
  const Vec3d camera(-p.y() + 0.1, -p.z() - 0.2, p.x() + 0.3);
  const double c = std::cos(M_PI / 6.0), s = std::sin(M_PI / 6.0);
  const Vec3d world(c * camera.x() + s * camera.z() + 5.0, camera.y() + 1.0, -s * camera.x() + c * camera.z() - 2.0);
  EXPECT_LT((velodyneToWorld.transform(p) - world).length(), 1e-8) << velodyneToWorld.transform(p) << " " << world;
  const Vec3d frame0 = kittiVelodyneToWorld(readKittiCameraToWorld(dir.path("00.txt"), 0),
                                            readKittiVelodyneToCamera(dir.path("calib.txt")))
                           .transform(p);
  EXPECT_LT((frame0 - camera).length(), 1e-8);
}

// A sweep whose velodyne pose is the turned scanner's, given as KITTI
// odometry gives it: the frame's camera pose and Tr.
TEST(PointScans, KittiSweepWithOdometryPosesLandsOnTheSphere) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  const std::vector<Vec3d> points = sensorPoints(grid);
  test::writeBytes(dir.path("000002.bin"), test::kittiBinBytes(points));
  const Mat4d cameraToWorld = kittiTr().inverse() * grid.scannerToWorld;  // velodyne = Tr then pose
  writeText(dir.path("calib.txt"), kittiCalib(kittiTr()));
  writeText(dir.path("00.txt"), test::kittiTransformText(kittiPose()) + "\n" + test::kittiTransformText(kittiPose()) +
                                    "\n" + test::kittiTransformText(cameraToWorld) + "\n");
  writeText(dir.path("scans.json"), R"({"scans": [{"format": "kitti-bin", "file": "000002.bin",
      "poses": "00.txt", "calib": "calib.txt", "frame": 2}]})");
  const RangeMap map = loadManifest(dir.path("scans.json")).at(0);
  expectSameMatrix(map.mapToWorld(), grid.scannerToWorld, 1e-8);
  expectTheSphere(map, grid, points.size(), kFloatPrecision);
}

TEST(PointScans, XyzFieldsCommentsAndColours) {
  TempDir dir;
  writeText(dir.path("plain.xyz"), "# a comment\n\n1 2 3\n  4 5 6\r\n#7 8 9\n");
  const PointCloud plain = readXyzPoints(dir.path("plain.xyz"));
  EXPECT_EQ(plain.points, (std::vector<Vec3d>{Vec3d(1, 2, 3), Vec3d(4, 5, 6)}));
  EXPECT_TRUE(plain.colours.empty());
  writeText(dir.path("intensity.txt"), "1 2 3 0.5\n4 5 6 -12\n");
  EXPECT_TRUE(readPointCloud(dir.path("intensity.txt")).colours.empty());
  writeText(dir.path("colour.xyz"), "1 2 3 0 128 255\n4 5 6 1 2 3\n");
  EXPECT_EQ(readXyzPoints(dir.path("colour.xyz")).colours, (std::vector<Rgb8>{{0, 128, 255}, {1, 2, 3}}));
  writeText(dir.path("both.XYZ"), "1 2 3 0.5 10 20 30\n");
  const PointCloud both = readPointCloud(dir.path("both.XYZ"));
  EXPECT_EQ(both.points, std::vector<Vec3d>{Vec3d(1, 2, 3)});
  EXPECT_EQ(both.colours, std::vector<Rgb8>{Rgb8({10, 20, 30})});
}

TEST(PointScans, PlyColoursOfUcharOrFloat) {
  TempDir dir;
  const std::vector<Vec3d> points{Vec3d(1, 2, 3), Vec3d(-1, 0.5, 2)};
  writeText(dir.path("uchar.ply"), test::plyPoints(points, {{1, 2, 3}, {250, 251, 252}}, true));
  const PointCloud uchar = readPlyPoints(dir.path("uchar.ply"));
  EXPECT_EQ(uchar.points, points);
  EXPECT_EQ(uchar.colours, (std::vector<Rgb8>{{1, 2, 3}, {250, 251, 252}}));
  writeText(dir.path("float.ply"),
            "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
            "property float red\nproperty float green\nproperty float blue\nproperty float nx\nend_header\n"
            "1 2 3 0 0.5 1 0\n4 5 6 1 0.25 0 0\n");
  EXPECT_EQ(readPlyPoints(dir.path("float.ply")).colours, (std::vector<Rgb8>{{0, 128, 255}, {255, 64, 0}}));
  writeText(dir.path("mesh.ply"), "ply\nformat ascii 1.0\nelement vertex 3\nproperty int x\nproperty int y\n"
                                  "property int z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                  "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const PointCloud mesh = readPointCloud(dir.path("mesh.ply"));
  EXPECT_EQ(mesh.points.size(), 3u);
  EXPECT_TRUE(mesh.colours.empty());
}

TEST(PointScans, TheNoiseIsTheOptionsOrTheEntrys) {
  TempDir dir;
  const test::PtxGrid grid = test::turnedGrid();
  writeText(dir.path("sphere.xyz"), test::xyzText(inWorld(sensorPoints(grid), grid.scannerToWorld)));
  writeText(dir.path("scans.json"), R"({"scans": [{"format": "points", "file": "sphere.xyz", "origin": [1, 2, 3]},
      {"format": "points", "file": "sphere.xyz", "origin": [1, 2, 3], "sigma": 0.03}]})");
  ScanLoadOptions options;
  options.setSigma(0.01);
  const std::vector<RangeMap> maps = loadManifest(dir.path("scans.json"), options);
  EXPECT_DOUBLE_EQ(maps.at(0).sigma(), 0.01);
  EXPECT_DOUBLE_EQ(maps.at(1).sigma(), 0.03);
}

}  // namespace
}  // namespace levelfuse::io
