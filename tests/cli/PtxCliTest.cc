// PTX files given to the converter: a ball seen by eight scanners around it,
// their scans in one file, described by info and reconstructed.

#include "BallScans.h"
#include "CliSupport.h"
#include "support/Files.h"
#include "support/PtxFiles.h"

#include <gtest/gtest.h>

namespace levelfuse {
namespace {

class PtxCli : public Cli {
 protected:
  /// The ball's eight scans (BallScans.h) in one file, the points in the
  /// scanner's frame, the transform its pose.
  std::string ballScans() {
    std::string text;
    for (int k = 0; k < test::kBallScanners; ++k) {
      const test::PtxGrid grid = test::ballScannerGrid(k);
      text += test::ptxScanText(grid, test::ballScanPoints(grid), test::PtxFrame::kScanner);
    }
    test::writeText(path("ball.ptx"), text);
    return path("ball.ptx");
  }
};

TEST_F(PtxCli, InfoDescribesEachScanOfTheFile) {
  const CliRun info = levelfuse("info --json " + ballScans());
  ASSERT_EQ(info.exitCode, 0) << info.output;
  const nlohmann::json j = jsonOf(info);
  test::expectBallInfo(j, 1e-6);
  EXPECT_EQ(j["scans"][0]["name"], "ball scan 1");
  EXPECT_EQ(j["scans"][7]["name"], "ball scan 8");
}

// The scans see the ball alone: the space between their fields of view, which
// no ray crossed, stays closed in the level set, and --trim-unseen leaves it
// out of the mesh.
TEST_F(PtxCli, ReconstructFindsTheBall) {
  const CliRun run = levelfuse("reconstruct " + ballScans() + " --voxel-size 0.02 --sigma 0.005 --trim-unseen --mesh " +
                               path("ball.ply") + " --json");
  test::expectBallReconstruction(run, path("ball.ply"));
}

}  // namespace
}  // namespace levelfuse
