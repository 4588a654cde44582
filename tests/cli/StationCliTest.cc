// A real terrestrial station given to the converter with its defaults: the
// pump room of ../shared/data/e57, one E57 scan seen from where the scanner
// stood, reconstructed as the scene it is.

#include "CliSupport.h"
#include "support/TestSupport.h"

#include <levelfuse/io/Ply.h>

#include <gtest/gtest.h>

#include <filesystem>

namespace levelfuse {
namespace {

class StationCli : public Cli {};

TEST_F(StationCli, InfoDescribesTheColouredStation) {
  const std::string pump = test::sharedData("e57/pumpA.e57");
  if (pump.empty()) GTEST_SKIP() << "../shared/data is absent";
  const CliRun info = levelfuse("info --json " + pump);
  ASSERT_EQ(info.exitCode, 0) << info.output;
  const nlohmann::json scan = jsonOf(info)["scans"][0];
  EXPECT_EQ(scan["name"], "pumpA");
  EXPECT_EQ(scan["projection"], "spherical");
  EXPECT_TRUE(scan["coloured"].get<bool>());
  EXPECT_GE(scan["readings"].get<std::size_t>(), 155201u * 99 / 100);
  EXPECT_NEAR(scan["angular_grid"]["azimuth_step"].get<double>(), 0.25, 0.01);  // degrees
}

// The station is a scene: one grid, no prior, what no ray saw left out of the
// mesh and the preview, which looks from the station. Its points lie on the
// surface (within a voxel) and none far beyond it, and the mesh is coloured.
TEST_F(StationCli, ThePumpRoomIsReconstructedAsASceneFromItsDefaults) {
  const std::string pump = test::sharedData("e57/pumpA.e57");
  if (pump.empty()) GTEST_SKIP() << "../shared/data is absent";
  const CliRun run = levelfuse("reconstruct " + pump + " -o " + path("pump.vdb") + " --mesh " + path("pump.ply") +
                               " --preview " + path("pump.png") + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const nlohmann::json j = jsonOf(run);
  EXPECT_EQ(j["levels"], 1);
  EXPECT_EQ(j["beta"], 0.0);
  EXPECT_TRUE(j["trimmed_unseen"].get<bool>());
  EXPECT_LT(j["voxel_size"].get<double>(), 0.01);  // the rays' spacing at the median range, not at the farthest
  EXPECT_GE(j["fit"]["within_voxel"].get<double>(), 0.95);
  EXPECT_LE(j["fit"]["beyond_band"].get<double>(), 0.01);
  const io::PlyData mesh = io::readPly(path("pump.ply"));
  const io::PlyElement* vertices = mesh.element("vertex");
  ASSERT_TRUE(vertices);
  EXPECT_GT(vertices->count, 100000u);
  EXPECT_TRUE(vertices->property("red") >= 0) << "the mesh carries the scan's colours";
  EXPECT_GT(std::filesystem::file_size(path("pump.png")), 10000u);
}

}  // namespace
}  // namespace levelfuse
