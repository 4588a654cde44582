// PTX files given to the converter: a ball seen by eight scanners around it,
// their scans in one file, described by info and reconstructed.

#include "CliSupport.h"
#include "support/Files.h"
#include "support/PtxFiles.h"

#include <levelfuse/io/Ply.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

constexpr double kBallRadius = 0.5;
constexpr double kScannerDistance = 2.0;
constexpr int kScanners = 8;

class PtxCli : public Cli {
 protected:
  /// A ball of radius 0.5 at the origin, scanned from eight tripods 2 m
  /// away around it, every other one above it and the others below (45
  /// degrees up or down), each scan 51 x 51 rays about 0.012 rad apart (512
  /// a turn) about the ball; the points in the scanner's frame, the
  /// transform its pose.
  std::string ballScans() {
    std::string text;
    for (int k = 0; k < kScanners; ++k) {
      const double around = k * M_PI / 4.0, up = (k % 2 == 0 ? 1.0 : -1.0) * M_PI / 4.0;
      const Vec3d position = Vec3d(std::cos(around), std::sin(around), std::tan(up)) * kScannerDistance * std::cos(up);
      test::PtxGrid grid;
      grid.columns = grid.rows = 51;
      grid.azimuthStart = -0.3;
      grid.elevationStart = -up - 0.3;
      grid.azimuthStep = grid.elevationStep = 2.0 * M_PI / 512.0;
      grid.scannerToWorld = test::scannerLookingAt(position, Vec3d(0.0));
      const Vec3d ballFromScanner = grid.scannerToWorld.inverse().transform(Vec3d(0.0));
      text += test::ptxScanText(grid, test::scanPoints(grid, test::sphere(ballFromScanner, kBallRadius)),
                                test::PtxFrame::kScanner);
    }
    test::writeText(path("ball.ptx"), text);
    return path("ball.ptx");
  }
};

TEST_F(PtxCli, InfoDescribesEachScanOfTheFile) {
  const CliRun info = levelfuse("info --json " + ballScans());
  ASSERT_EQ(info.exitCode, 0) << info.output;
  const nlohmann::json j = jsonOf(info);
  ASSERT_EQ(j["scans"].size(), static_cast<std::size_t>(kScanners));
  EXPECT_EQ(j["scans"][0]["name"], "ball scan 1");
  EXPECT_EQ(j["scans"][7]["name"], "ball scan 8");
  EXPECT_EQ(j["scans"][0]["projection"], "spherical");
  EXPECT_DOUBLE_EQ(j["scans"][0]["sigma"].get<double>(), 0.002);
  EXPECT_NEAR(j["scans"][2]["scanner_position"][1].get<double>(), kScannerDistance * std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(j["scans"][2]["scanner_position"][2].get<double>(), kScannerDistance * std::sqrt(0.5), 1e-6);
  // The readings lie on the ball.
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GT(j["bounds"][0][axis].get<double>(), -kBallRadius - 1e-6);
    EXPECT_LT(j["bounds"][1][axis].get<double>(), kBallRadius + 1e-6);
  }
}

// The scans see the ball alone: the space between their fields of view, which
// no ray crossed, stays closed in the level set, and --trim-unseen leaves it
// out of the mesh.
TEST_F(PtxCli, ReconstructFindsTheBall) {
  const CliRun run = levelfuse("reconstruct " + ballScans() + " --voxel-size 0.02 --sigma 0.005 --trim-unseen --mesh " +
                               path("ball.ply") + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const nlohmann::json j = jsonOf(run);
  EXPECT_EQ(j["scans"], kScanners);
  EXPECT_LT(j["fit"]["rms"].get<double>(), 0.01);  // half a voxel
  const io::PlyData mesh = io::readPly(path("ball.ply"));
  const io::PlyElement* vertices = mesh.element("vertex");
  ASSERT_TRUE(vertices);
  ASSERT_GT(vertices->count, 1000u);
  double sum = 0.0, farthest = 0.0;
  for (std::size_t i = 0; i < vertices->count; ++i) {
    const double radius = Vec3d(vertices->values[0][i], vertices->values[1][i], vertices->values[2][i]).length();
    sum += radius;
    farthest = std::max(farthest, std::fabs(radius - kBallRadius));
  }
  EXPECT_NEAR(sum / static_cast<double>(vertices->count), kBallRadius, 0.005);
  EXPECT_LT(farthest, 0.05);  // two and a half voxels: the rims of the unseen parts left out
}

}  // namespace
}  // namespace levelfuse
