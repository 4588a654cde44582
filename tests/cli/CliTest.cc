// The levelfuse command-line converter, run as a user runs it.

#include "CliSupport.h"
#include "support/TestSupport.h"

#include <levelfuse/io/vdb/VdbFile.h>
#include <levelfuse/levelset/Components.h>

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

namespace levelfuse {
namespace {

namespace fs = std::filesystem;

TEST_F(Cli, VersionAndHelp) {
  const CliRun version = levelfuse("--version");
  EXPECT_EQ(version.exitCode, 0);
  EXPECT_NE(version.output.find("levelfuse 0."), std::string::npos) << version.output;
  EXPECT_NE(version.output.find("OpenVDB"), std::string::npos);
  const CliRun help = levelfuse("--help");
  EXPECT_EQ(help.exitCode, 0);
  EXPECT_NE(help.output.find("evolve"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("Exit codes"), std::string::npos);
  const CliRun evolveHelp = levelfuse("evolve --help");
  EXPECT_EQ(evolveHelp.exitCode, 0);
  EXPECT_NE(evolveHelp.output.find("Examples:"), std::string::npos);
}

TEST_F(Cli, UsageErrorsExitWithTwo) {
  EXPECT_EQ(levelfuse("").exitCode, 2);
  EXPECT_EQ(levelfuse("frobnicate").exitCode, 2);
  const CliRun missingOutput = levelfuse("evolve");
  EXPECT_EQ(missingOutput.exitCode, 2);
  EXPECT_NE(missingOutput.output.find("--output"), std::string::npos) << missingOutput.output;
  const CliRun badShape = levelfuse("evolve --shape cube -o " + path("x.vdb"));
  EXPECT_EQ(badShape.exitCode, 2);
  EXPECT_NE(badShape.output.find("cube"), std::string::npos);
  EXPECT_EQ(filesInDir(), 0u);
}

TEST_F(Cli, EvolveWritesALevelSetThatSplits) {
  const std::string out = path("dumbbell.vdb");
  const CliRun run = levelfuse("evolve --shape dumbbell --resolution 64 --json -o " + out);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("\"components_after\": 2"), std::string::npos) << run.output;
  const auto grids = io::readVdb(out);
  ASSERT_EQ(grids->size(), 1u);
  const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>((*grids)[0]);
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(grid->getName(), "surface");
  EXPECT_NEAR(grid->background(), 3.0 * grid->voxelSize()[0], 1e-6);
  EXPECT_EQ(insideComponents(*grid), 2);
  EXPECT_EQ(filesInDir(), 1u);  // no temporary left behind
}

TEST_F(Cli, OutputIsReadByVdbPrint) {
  if (std::system("command -v vdb_print > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "vdb_print is not installed (Debian package libopenvdb-tools)";
  const std::string out = path("sphere.vdb");
  ASSERT_EQ(levelfuse("evolve --shape sphere --resolution 32 -o " + out).exitCode, 0);
  FILE* pipe = popen(("vdb_print -l " + out + " 2>&1").c_str(), "r");
  ASSERT_TRUE(pipe);
  std::string text;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof(buffer), pipe)) text.append(buffer, n);
  EXPECT_EQ(pclose(pipe), 0) << text;
  EXPECT_NE(text.find("Name: surface"), std::string::npos) << text;
  EXPECT_NE(text.find("class: level set"), std::string::npos) << text;
  EXPECT_NE(text.find("levelfuse_flow: curvature"), std::string::npos) << text;
}

TEST_F(Cli, FailedWriteLeavesNoFileAndKeepsTheOldOne) {
  const CliRun run = levelfuse("evolve --resolution 16 -o " + path("missing/dir/out.vdb"));
  EXPECT_EQ(run.exitCode, 1);
  EXPECT_NE(run.output.find("missing/dir/out.vdb"), std::string::npos) << run.output;
  EXPECT_EQ(filesInDir(), 0u);

  // An output that cannot be replaced (a directory in its place) stays as it was.
  fs::create_directories(path("taken.vdb"));
  std::ofstream(path("taken.vdb/keep")) << "keep";
  const CliRun blocked = levelfuse("evolve --resolution 16 -o " + path("taken.vdb"));
  EXPECT_EQ(blocked.exitCode, 1);
  EXPECT_TRUE(fs::exists(path("taken.vdb/keep")));
  EXPECT_EQ(filesInDir(), 1u);
}

TEST_F(Cli, ThreadCountDoesNotChangeTheResult) {
  ASSERT_EQ(levelfuse("evolve --shape two-spheres --flow grow --resolution 48 --threads 1 -o " + path("a.vdb")).exitCode, 0);
  ASSERT_EQ(levelfuse("evolve --shape two-spheres --flow grow --resolution 48 --threads 2 -o " + path("b.vdb")).exitCode, 0);
  const auto a = openvdb::gridPtrCast<openvdb::FloatGrid>((*io::readVdb(path("a.vdb")))[0]);
  const auto b = openvdb::gridPtrCast<openvdb::FloatGrid>((*io::readVdb(path("b.vdb")))[0]);
  ASSERT_TRUE(a && b);
  std::string why;
  EXPECT_TRUE(test::identical(*a, *b, &why)) << why;
}

TEST_F(Cli, ALevelSetHoldingNaNIsNamedAndNotMeshed) {
  // FuzzVdb's find: OpenVDB's mesher threw on the NaN from inside its TBB tasks.
  openvdb::FloatGrid::Ptr ball = test::makeSphere(5.0);
  ball->setName("ball");
  ball->tree().setValueOff(openvdb::Coord(5, 0, 0), std::numeric_limits<float>::quiet_NaN());
  io::writeVdb(path("nan.vdb"), {ball});
  const CliRun info = levelfuse("info " + path("nan.vdb"));
  EXPECT_EQ(info.exitCode, 0) << info.output;
  EXPECT_NE(info.output.find("not finite at voxel [5, 0, 0]"), std::string::npos) << info.output;
  const CliRun mesh = levelfuse("mesh " + path("nan.vdb") + " -o " + path("nan.ply"));
  EXPECT_EQ(mesh.exitCode, 1) << mesh.output;
  EXPECT_EQ(mesh.output.rfind("levelfuse mesh: error: " + path("nan.vdb") + ": the grid 'ball' holds a value that "
                              "is not finite at voxel [5, 0, 0]",
                              0),
            0u)
      << mesh.output;
  EXPECT_EQ(std::count(mesh.output.begin(), mesh.output.end(), '\n'), 1) << mesh.output;
  EXPECT_FALSE(fs::exists(path("nan.ply")));
}

}  // namespace
}  // namespace levelfuse
