// Point clouds given to the converter through a manifest: a ball seen by
// eight sensors around it, their points written as XYZ (with the sensor's
// origin), PLY (with its pose) and KITTI sweeps (in the sensor's frame),
// described by info and reconstructed.

#include "BallScans.h"
#include "CliSupport.h"
#include "support/Files.h"
#include "support/LaserSweeps.h"
#include "support/PointFiles.h"
#include "support/PtxFiles.h"

#include <levelfuse/io/vdb/VdbFile.h>
#include <levelfuse/recon/DataFit.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

class PointsCli : public Cli {
 protected:
  /// The ball's eight scans (BallScans.h): scans 0, 3 and 6 as XYZ in the
  /// world with the sensor's origin, 1, 4 and 7 as binary PLY in the world
  /// with its pose, 2 and 5 as KITTI sweeps in the sensor's frame with its
  /// pose. Returns the manifest.
  std::string ballManifest() {
    std::string entries;
    for (int k = 0; k < test::kBallScanners; ++k) {
      const test::PtxGrid grid = test::ballScannerGrid(k);
      std::vector<Vec3d> sensorPoints, worldPoints;
      for (const Vec3d& p : test::ballScanPoints(grid))
        if (p != Vec3d(0.0)) {
          sensorPoints.push_back(p);
          worldPoints.push_back(grid.scannerToWorld.transform(p));
        }
      const std::string name = "scan" + std::to_string(k);
      const std::string pose = test::manifestPose(grid.scannerToWorld);
      const Vec3d position = grid.scannerToWorld.getTranslation();
      std::string entry;
      if (k % 3 == 0) {
        test::writeText(path(name + ".xyz"), test::xyzText(worldPoints));
        entry = R"({"format": "points", "file": ")" + name + R"(.xyz", "origin": [)" + std::to_string(position.x()) +
                ", " + std::to_string(position.y()) + ", " + std::to_string(position.z()) + "]}";
      } else if (k % 3 == 1) {
        test::writeText(path(name + ".ply"), test::plyPoints(worldPoints, test::someColours(worldPoints.size()), true));
        entry = R"({"format": "points", "file": ")" + name + R"(.ply", "pose": )" + pose + "}";
      } else {
        test::writeBytes(path(name + ".bin"), test::kittiBinBytes(sensorPoints));
        entry = R"({"format": "kitti-bin", "file": ")" + name + R"(.bin", "pose": )" + pose + "}";
      }
      entries += (entries.empty() ? "" : ",\n") + entry;
    }
    test::writeText(path("scans.json"), "{\"scans\": [\n" + entries + "\n]}\n");
    return path("scans.json");
  }
};

TEST_F(PointsCli, InfoDescribesEachScan) {
  const CliRun info = levelfuse("info --json " + ballManifest());
  ASSERT_EQ(info.exitCode, 0) << info.output;
  const nlohmann::json j = jsonOf(info);
  test::expectBallInfo(j, 1e-5);  // KITTI's float32 coordinates
  EXPECT_EQ(j["scans"][0]["name"], "scan0.xyz");
  EXPECT_EQ(j["scans"][1]["name"], "scan1.ply");
  EXPECT_EQ(j["scans"][2]["name"], "scan2.bin");
}

// A sensor's lasers spaced unevenly, a degree apart below the horizon and
// half a degree above: info gives the rows the estimate keeps.
TEST_F(PointsCli, InfoGivesTheRowsOfUnevenLasers) {
  const std::vector<double> lasers{-4.0, -3.0, -2.0, -1.0, -0.5, 0.0, 0.5, 1.0};
  std::vector<Vec3d> points;
  for (const double elevation : lasers)
    for (int c = -45; c <= 45; ++c) {
      const double e = elevation * M_PI / 180.0, a = c * M_PI / 180.0;
      points.push_back(Vec3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)) * (5.0 / std::cos(a)));
    }
  test::writeText(path("sweep.xyz"), test::xyzText(points));
  test::writeText(path("scans.json"), R"({"scans": [{"format": "points", "file": "sweep.xyz", "origin": [0, 0, 0]}]})");
  const CliRun info = levelfuse("info --json " + path("scans.json"));
  ASSERT_EQ(info.exitCode, 0) << info.output;
  const nlohmann::json grid = jsonOf(info)["scans"][0]["angular_grid"];
  EXPECT_NEAR(grid["azimuth_step"].get<double>(), 1.0, 1e-6);
  ASSERT_EQ(grid["row_elevations"].size(), lasers.size());
  for (std::size_t r = 0; r < lasers.size(); ++r) EXPECT_NEAR(grid["row_elevations"][r].get<double>(), lasers[r], 1e-6);
  const CliRun text = levelfuse("info " + path("scans.json"));
  EXPECT_NE(text.output.find("spherical 91 x 8, "), std::string::npos) << text.output;
  EXPECT_NE(text.output.find(", steps 1 deg x 8 rows 0.5 to 1 deg apart"), std::string::npos)
      << text.output;
}

// A KITTI sweep listed laser by laser in firing order, two blocks of lasers
// with their apexes 8 cm apart: a map per block, the returns kept, and the
// street corner around the sensor reconstructed within a voxel of them,
// where binning the same returns by their directions from the sensor's
// origin (steps given) misplaces them by the apexes' parallax.
TEST_F(PointsCli, AKittiSweepBecomesAMapPerBlockOfLasers) {
  const std::vector<Vec3d> points = test::streetCornerSweep(test::streetSensor());
  test::writeBytes(path("000000.bin"), test::kittiBinBytes(points));
  const std::string identity = R"("pose": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])";
  test::writeText(path("sweep.json"),
                  R"({"scans": [{"format": "kitti-bin", "file": "000000.bin", "sigma": 0.01, )" + identity + "}]}");
  test::writeText(path("binned.json"), R"({"scans": [{"format": "kitti-bin", "file": "000000.bin", "sigma": 0.01, )"
                                       R"("azimuth_step": 0.1857, "elevation_step": 0.5, )" + identity + "}]}");
  const CliRun info = levelfuse("info --json " + path("sweep.json"));
  ASSERT_EQ(info.exitCode, 0) << info.output;
  const nlohmann::json scans = jsonOf(info)["scans"];
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(scans[0]["name"], "000000.bin, lasers 9-16");
  EXPECT_EQ(scans[1]["name"], "000000.bin, lasers 1-8");
  std::size_t kept = 0;
  for (const nlohmann::json& scan : scans) kept += scan["points"].get<std::size_t>();
  EXPECT_GE(kept, static_cast<std::size_t>(0.995 * static_cast<double>(points.size())));
  EXPECT_LE(kept, points.size() + 2 * 8);  // a closed turn repeats its first column

  // The returns within 12 m of the sensor: the wall, the car and the road the lower lasers swept.
  std::vector<Vec3d> near;
  for (const Vec3d& p : points)
    if (std::hypot(p.x(), p.y()) < 12.0) near.push_back(p);
  const auto fitOf = [&](const std::string& manifest, const std::string& output) {
    const CliRun run = levelfuse("reconstruct " + path(manifest) + " --voxel-size 0.05 -q -o " + path(output));
    EXPECT_EQ(run.exitCode, 0) << run.output;
    const auto surface = openvdb::GridBase::grid<openvdb::FloatGrid>(io::readVdb(path(output))->at(0));
    return measureDataFit(*surface, near);
  };
  const DataFit lasers = fitOf("sweep.json", "lasers.vdb"), binned = fitOf("binned.json", "binned.vdb");
  RecordProperty("within_voxel_lasers", std::to_string(lasers.withinVoxel));
  RecordProperty("within_voxel_binned", std::to_string(binned.withinVoxel));
  EXPECT_GE(lasers.withinVoxel, 0.95);
  EXPECT_GE(lasers.withinVoxel, binned.withinVoxel + 0.1);
  EXPECT_LE(lasers.p90, 0.5 * 0.05);
}

// Two sweeps of the street corner 2 m apart, posed by KITTI odometry's files:
// fused, the returns of both lie within a voxel of the surface.
TEST_F(PointsCli, KittiSweepsPosedByTheirOdometryFuse) {
  const openvdb::math::Mat4d identity = openvdb::math::Mat4d::identity();
  openvdb::math::Mat4d moved = identity;
  moved.setTranslation(Vec3d(2.0, 0.0, 0.0));
  test::writeText(path("calib.txt"), "Tr: " + test::kittiTransformText(identity) + "\n");
  test::writeText(path("poses.txt"), test::kittiTransformText(identity) + "\n" + test::kittiTransformText(moved) + "\n");
  std::vector<Vec3d> near;
  for (int frame = 0; frame < 2; ++frame) {
    const Vec3d at(2.0 * frame, 0.0, 0.0);
    const std::vector<Vec3d> points = test::streetCornerSweep(test::streetSensor(), 7 + frame, at);
    test::writeBytes(path(std::to_string(frame) + ".bin"), test::kittiBinBytes(points));
    for (const Vec3d& p : points)
      if (std::hypot(p.x(), p.y()) < 12.0) near.push_back(p + at);
  }
  test::writeText(path("sequence.json"), R"({"scans": [
      {"format": "kitti-bin", "file": "0.bin", "poses": "poses.txt", "calib": "calib.txt", "frame": 0, "sigma": 0.01},
      {"format": "kitti-bin", "file": "1.bin", "poses": "poses.txt", "calib": "calib.txt", "frame": 1, "sigma": 0.01}]})");
  const CliRun run = levelfuse("reconstruct " + path("sequence.json") + " --voxel-size 0.05 --json -o " +
                               path("sequence.vdb"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_EQ(jsonOf(run)["scans"].get<int>(), 4);  // two blocks of lasers a sweep
  const auto surface = openvdb::GridBase::grid<openvdb::FloatGrid>(io::readVdb(path("sequence.vdb"))->at(0));
  const DataFit fit = measureDataFit(*surface, near);
  RecordProperty("within_voxel", std::to_string(fit.withinVoxel));
  EXPECT_GE(fit.withinVoxel, 0.95);
}

// Their steps estimated from the points, the maps are the scanners' grids.
TEST_F(PointsCli, ReconstructFindsTheBall) {
  const CliRun run = levelfuse("reconstruct " + ballManifest() + " --voxel-size 0.02 --sigma 0.005 --trim-unseen --mesh " +
                               path("ball.ply") + " --json");
  test::expectBallReconstruction(run, path("ball.ply"));
}

TEST_F(PointsCli, ABadPointFileIsOneLineNamingIt) {
  test::writeText(path("bad.xyz"), "1 2 3\n4 5 nan\n");
  test::writeText(path("scans.json"), R"({"scans": [{"format": "points", "file": "bad.xyz", "origin": [0, 0, 0]}]})");
  const CliRun run = levelfuse("info " + path("scans.json"));
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find(path("bad.xyz") + ": line 2: 'nan' is not a finite number"), std::string::npos)
      << run.output;
}

}  // namespace
}  // namespace levelfuse
