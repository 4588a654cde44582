// levelfuse with folders of depth frames: the TUM RGB-D layout recognised, and
// the depth options (--max-depth, --depth-scale, --frame-stride) checked and used.

#include "CliSupport.h"
#include "support/DepthFolders.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

namespace levelfuse {
namespace {

class DepthFolderCli : public Cli {
 protected:
  /// A TUM RGB-D folder: four 16 x 12 frames of the plane z = 2 from a camera
  /// tilted by 30 degrees, which sees it from about 1.8 to 3.1 m.
  std::string tumFolder() {
    test::TumFixture f;
    for (int i = 0; i < 4; ++i) {
      test::CameraPose pose;
      pose.position = openvdb::Vec3d(0.05 * i, 0.0, 0.0);
      pose.rotation = test::rotationAbout(openvdb::Vec3d(1.0, 0.0, 0.0), 30.0);
      f.poses.push_back({20.0 + 0.1 * i, pose});
      f.frameTimes.push_back(20.0 + 0.1 * i);
    }
    test::writeTumFolder(path("tum"), f);
    return path("tum");
  }

  nlohmann::json summary(const std::string& arguments) {
    const CliRun run = levelfuse("reconstruct " + arguments + " --linear --json -o " + path("out.vdb"));
    EXPECT_EQ(run.exitCode, 0) << run.output;
    try {
      return nlohmann::json::parse(run.output);
    } catch (const std::exception&) {
      ADD_FAILURE() << "not JSON:\n" << run.output;
      return nlohmann::json::object();
    }
  }
};

TEST_F(DepthFolderCli, ReadsATumFolderWithItsOptions) {
  const std::string folder = tumFolder();
  const nlohmann::json all = summary(folder);
  EXPECT_EQ(all["scans"], 4);
  EXPECT_EQ(all["readings"], 4 * 16 * 12);
  EXPECT_EQ(summary(folder + " --frame-stride 2")["scans"], 2);
  const int near = summary(folder + " --max-depth 2.3")["readings"];
  EXPECT_GT(near, 0);
  EXPECT_LT(near, 4 * 16 * 12);
}

TEST_F(DepthFolderCli, RefusesDepthOptionsOutOfRange) {
  const std::string folder = tumFolder();
  for (const char* option : {"--max-depth 0", "--max-depth -1", "--max-depth inf", "--max-depth nan",
                             "--max-depth 2m", "--depth-scale inf", "--depth-scale 0", "--frame-stride 0"}) {
    const CliRun run = levelfuse("reconstruct " + folder + " " + option + " -o " + path("out.vdb"));
    EXPECT_EQ(run.exitCode, 2) << option << ": " << run.output;
    EXPECT_FALSE(fs::exists(path("out.vdb"))) << option;
  }
}

}  // namespace
}  // namespace levelfuse
