// Point clouds given to the converter through a manifest: a ball seen by
// eight sensors around it, their points written as XYZ (with the sensor's
// origin), PLY (with its pose) and KITTI sweeps (in the sensor's frame),
// described by info and reconstructed.

#include "BallScans.h"
#include "CliSupport.h"
#include "support/Files.h"
#include "support/PointFiles.h"
#include "support/PtxFiles.h"

#include <gtest/gtest.h>

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
