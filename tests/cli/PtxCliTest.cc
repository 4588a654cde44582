// PTX files given to the converter: a ball seen by four scanners around it,
// their scans in one file, described by info and reconstructed.

#include "CliSupport.h"
#include "support/Files.h"
#include "support/PtxFiles.h"
#include "support/TestSupport.h"

#include <levelfuse/io/VdbFile.h>

#include <gtest/gtest.h>

#include <cmath>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

constexpr double kBallRadius = 0.5;
constexpr double kScannerDistance = 2.0;

class PtxCli : public Cli {
 protected:
  /// A ball of radius 0.5 at the origin, scanned from four tripods 2 m away
  /// at its height, each scan 51 x 51 rays about 0.012 rad apart (512 a
  /// turn) about the ball; the points in the scanner's frame, the transform
  /// its pose.
  std::string ballScans() {
    std::string text;
    for (int k = 0; k < 4; ++k) {
      const double angle = k * M_PI / 2.0;
      test::PtxGrid grid;
      grid.columns = grid.rows = 51;
      grid.azimuthStart = grid.elevationStart = -0.3;
      grid.azimuthStep = grid.elevationStep = 2.0 * M_PI / 512.0;
      grid.scannerToWorld = test::scannerLookingAt(
          Vec3d(kScannerDistance * std::cos(angle), kScannerDistance * std::sin(angle), 0.0), Vec3d(0.0));
      const auto ball = test::sphere(Vec3d(kScannerDistance, 0.0, 0.0), kBallRadius);
      text += test::ptxScanText(grid, test::scanPoints(grid, ball), test::PtxFrame::kScanner);
    }
    test::writeText(path("ball.ptx"), text);
    return path("ball.ptx");
  }
};

TEST_F(PtxCli, InfoDescribesEachScanOfTheFile) {
  const CliRun info = levelfuse("info --json " + ballScans());
  ASSERT_EQ(info.exitCode, 0) << info.output;
  const nlohmann::json j = jsonOf(info);
  ASSERT_EQ(j["scans"].size(), 4u);
  EXPECT_EQ(j["scans"][0]["name"], "ball scan 1");
  EXPECT_EQ(j["scans"][3]["name"], "ball scan 4");
  EXPECT_EQ(j["scans"][0]["projection"], "spherical");
  EXPECT_DOUBLE_EQ(j["scans"][0]["sigma"].get<double>(), 0.002);
  EXPECT_NEAR(j["scans"][1]["scanner_position"][1].get<double>(), kScannerDistance, 1e-6);
  // The readings lie on the ball.
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GT(j["bounds"][0][axis].get<double>(), -kBallRadius - 1e-6);
    EXPECT_LT(j["bounds"][1][axis].get<double>(), kBallRadius + 1e-6);
  }
}

TEST_F(PtxCli, ReconstructFindsTheBall) {
  const CliRun run = levelfuse("reconstruct " + ballScans() + " --voxel-size 0.02 --sigma 0.005 -o " +
                               path("ball.vdb") + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const nlohmann::json j = jsonOf(run);
  EXPECT_EQ(j["scans"], 4);
  EXPECT_LT(j["fit"]["rms"].get<double>(), 0.01);  // half a voxel
  const openvdb::GridPtrVecPtr grids = io::readVdb(path("ball.vdb"));
  const openvdb::FloatGrid::Ptr surface = openvdb::GridBase::grid<openvdb::FloatGrid>(grids->at(0));  // 'surface'
  ASSERT_TRUE(surface);
  const test::RadiusFit fit = test::fitRadius(*surface, Vec3d(0.0));
  EXPECT_NEAR(fit.mean, kBallRadius, 0.02);
}

}  // namespace
}  // namespace levelfuse
