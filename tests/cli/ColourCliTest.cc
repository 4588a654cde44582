// Colour through the converter: synthetic scans painted in two halves, their
// colours written beside them, reconstructed into a .vdb with a "Cd" grid, a
// coloured mesh and a coloured preview; `levelfuse mesh` keeps the colour.

#include "CliSupport.h"
#include "support/Files.h"

#include <levelfuse/io/Ply.h>
#include <levelfuse/io/vdb/VdbFile.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace levelfuse {
namespace {

class ColourCli : public Cli {
 protected:
  /// The unit sphere from six views, its upper half red and its lower half blue.
  std::string paintedSphere() {
    const CliRun synth = levelfuse("synth --shape sphere --resolution 80 --noise 0.005 --paint halves -o " + path("scans"));
    EXPECT_EQ(synth.exitCode, 0) << synth.output;
    return path("scans/scans.json");
  }
};

/// How many vertices of a coloured PLY mesh, away from z = 0 by more than
/// `seam`, are not the colour of their half: red (200, 40, 30) above, blue
/// (30, 60, 200) below, within 5 of 255.
std::size_t verticesOffColour(const io::PlyElement& v, double seam) {
  const int z = v.property("z"), red = v.property("red"), blue = v.property("blue");
  std::size_t off = 0;
  for (std::size_t i = 0; i < v.count; ++i) {
    if (std::fabs(v.values[z][i]) < seam) continue;
    const bool above = v.values[z][i] > 0.0;
    off += std::fabs(v.values[red][i] - (above ? 200 : 30)) > 5 || std::fabs(v.values[blue][i] - (above ? 30 : 200)) > 5;
  }
  return off;
}

TEST_F(ColourCli, ReconstructWritesTheColourBesideTheSurfaceAndOnTheMesh) {
  const std::string scans = paintedSphere();
  EXPECT_TRUE(std::filesystem::exists(path("scans/scan0.colour.png")));
  const CliRun run = levelfuse("reconstruct " + scans + " -o " + path("s.vdb") + " --mesh " + path("s.ply") +
                               " --preview " + path("s.png") + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const openvdb::GridPtrVecPtr grids = io::readVdb(path("s.vdb"));
  openvdb::Vec3fGrid::Ptr colour;
  for (const auto& grid : *grids)
    if (grid->getName() == "Cd") colour = openvdb::GridBase::grid<openvdb::Vec3fGrid>(grid);
  ASSERT_TRUE(colour);
  EXPECT_GT(colour->activeVoxelCount(), 10000u);
  const io::PlyData ply = io::readPly(path("s.ply"));
  const io::PlyElement& vertices = *ply.element("vertex");
  ASSERT_GE(vertices.property("red"), 0);
  const double voxel = jsonOf(run)["voxel_size"].get<double>();
  EXPECT_GT(vertices.count, 5000u);
  EXPECT_EQ(verticesOffColour(vertices, 5.0 * voxel), 0u);

  // The mesh command finds the colour grid beside the level set.
  const CliRun mesh = levelfuse("mesh " + path("s.vdb") + " -o " + path("again.ply") + " --json");
  ASSERT_EQ(mesh.exitCode, 0) << mesh.output;
  EXPECT_TRUE(jsonOf(mesh)["coloured"].get<bool>());
  const io::PlyData againPly = io::readPly(path("again.ply"));
  const io::PlyElement& again = *againPly.element("vertex");
  EXPECT_EQ(again.count, vertices.count);
  EXPECT_EQ(verticesOffColour(again, 5.0 * voxel), 0u);
}

TEST_F(ColourCli, InfoSaysWhichScansAreColoured) {
  const CliRun info = levelfuse("info --json " + paintedSphere());
  ASSERT_EQ(info.exitCode, 0) << info.output;
  const nlohmann::json described = jsonOf(info);
  for (const auto& scan : described["scans"]) EXPECT_TRUE(scan["coloured"].get<bool>());
  EXPECT_NE(levelfuse("info " + path("scans/scans.json")).output.find(", coloured"), std::string::npos);
}

TEST_F(ColourCli, TheLinearSolutionIsColouredToo) {
  const CliRun run = levelfuse("reconstruct " + paintedSphere() + " --linear --mesh " + path("l.ply") + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const io::PlyData ply = io::readPly(path("l.ply"));
  const io::PlyElement& vertices = *ply.element("vertex");
  ASSERT_GE(vertices.property("red"), 0);
  EXPECT_EQ(verticesOffColour(vertices, 5.0 * jsonOf(run)["voxel_size"].get<double>()), 0u);
}

TEST_F(ColourCli, ScansWithoutColourGiveAPlainMesh) {
  ASSERT_EQ(levelfuse("synth --shape sphere --resolution 60 -o " + path("plain")).exitCode, 0);
  const CliRun run = levelfuse("reconstruct " + path("plain/scans.json") + " -o " + path("p.vdb") + " --mesh " +
                               path("p.ply"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_LT(io::readPly(path("p.ply")).element("vertex")->property("red"), 0);
  const openvdb::GridPtrVecPtr grids = io::readVdb(path("p.vdb"));
  for (const auto& grid : *grids) EXPECT_NE(grid->getName(), "Cd");
}

}  // namespace
}  // namespace levelfuse
