// Scenes: meshes and previews of depth frames leave out what no frame saw,
// the .vdb keeps the closed level set with its weight grid beside it.

#include "CliSupport.h"
#include "support/DepthFolders.h"
#include "support/TestSupport.h"

#include <levelfuse/io/Ply.h>
#include <levelfuse/io/vdb/VdbFile.h>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <map>
#include <utility>

namespace levelfuse {
namespace {

/// Edges of a PLY mesh's faces that only one face uses: none for a closed mesh.
std::size_t openEdges(const std::string& path) {
  const io::PlyData ply = io::readPly(path);
  const io::PlyElement* faces = ply.element("face");
  if (!faces) return 0;
  const std::vector<double>& items = faces->values[0];
  const std::vector<std::size_t>& offsets = faces->listOffsets[0];
  std::map<std::pair<long, long>, int> uses;
  for (std::size_t f = 0; f < faces->count; ++f)
    for (std::size_t k = offsets[f]; k < offsets[f + 1]; ++k) {
      const long a = static_cast<long>(items[k]);
      const long b = static_cast<long>(items[k + 1 < offsets[f + 1] ? k + 1 : offsets[f]]);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  std::size_t open = 0;
  for (const auto& edge : uses) open += edge.second == 1;
  return open;
}

class SceneCli : public Cli {
 protected:
  /// A 7-Scenes folder: three 64 x 48 frames of the plane z = 2 from cameras
  /// near the origin looking up +z, tilted a little.
  std::string depthFolder() {
    std::vector<test::CameraPose> poses(3);
    for (int i = 0; i < 3; ++i) {
      poses[i].position = openvdb::Vec3d(0.1 * i, 0.05 * i, 0.0);
      poses[i].rotation = test::rotationAbout(openvdb::Vec3d(1.0, 0.0, 0.0), 10.0 * i);
    }
    test::writeSevenScenesFolder(path("frames"), poses, PinholeProjection{48.0, 48.0, 31.5, 23.5}, 64, 48, 2.0);
    return path("frames");
  }
};

TEST_F(SceneCli, DepthFramesGiveATrimmedMeshByDefaultAndAClosedOneOnRequest) {
  const std::string frames = depthFolder();
  const std::string common = "reconstruct " + frames + " --voxel-size 0.05 --json ";
  const CliRun trimmed = levelfuse(common + "--mesh " + path("trimmed.ply") + " -o " + path("room.vdb"));
  ASSERT_EQ(trimmed.exitCode, 0) << trimmed.output;
  const CliRun closed = levelfuse(common + "--no-trim-unseen --mesh " + path("closed.ply"));
  ASSERT_EQ(closed.exitCode, 0) << closed.output;
  EXPECT_TRUE(jsonOf(trimmed)["trimmed_unseen"].get<bool>());
  EXPECT_FALSE(jsonOf(closed)["trimmed_unseen"].get<bool>());
  const std::size_t kept = jsonOf(trimmed)["triangles"], all = jsonOf(closed)["triangles"];
  // The space carving closes the plane into a slab; the frames saw only its
  // front: well under half of its surface stays.
  EXPECT_GT(kept, 100u);
  EXPECT_LT(kept, all / 2);
  EXPECT_EQ(openEdges(path("closed.ply")), 0u);
  EXPECT_GT(openEdges(path("trimmed.ply")), 0u);

  // The .vdb holds the closed level set and its weight grid.
  const openvdb::GridPtrVecPtr grids = io::readVdb(path("room.vdb"));
  ASSERT_EQ(grids->size(), 2u);
  const auto surface = openvdb::GridBase::grid<openvdb::FloatGrid>(grids->at(0));
  const auto weight = openvdb::GridBase::grid<openvdb::FloatGrid>(grids->at(1));
  ASSERT_TRUE(surface && weight);
  EXPECT_EQ(surface->getName(), "surface");
  EXPECT_EQ(surface->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_TRUE(surface->metaValue<bool>("levelfuse_scene"));
  EXPECT_EQ(weight->getName(), "weight");
  EXPECT_EQ(weight->getGridClass(), openvdb::GRID_UNKNOWN);
  EXPECT_EQ(weight->metaValue<std::string>("levelfuse_surface"), "surface");
  EXPECT_EQ(weight->metaValue<std::string>("levelfuse_units"), "readings");
  EXPECT_GT(weight->metaValue<double>("levelfuse_observed_weight"), 0.0);
  // The weight grid holds the leaves some reading faced, not the unseen faces.
  std::size_t facedLeaves = 0;
  EXPECT_TRUE(test::weighsTheBand(*weight, *surface, &facedLeaves));
  EXPECT_LT(facedLeaves, surface->tree().leafCount());

  // levelfuse mesh trims a scene's level set by its weight grid, or not.
  const CliRun meshed = levelfuse("mesh --json " + path("room.vdb") + " -o " + path("again.ply"));
  ASSERT_EQ(meshed.exitCode, 0) << meshed.output;
  EXPECT_EQ(jsonOf(meshed)["triangles"], kept);
  const CliRun whole = levelfuse("mesh --json --no-trim-unseen " + path("room.vdb") + " -o " + path("whole.ply"));
  ASSERT_EQ(whole.exitCode, 0) << whole.output;
  EXPECT_EQ(jsonOf(whole)["triangles"], all);
}

TEST_F(SceneCli, AStreetOfDepthFramesIsAScene) {
  // synth --shape street: depth frames along a façade, half a metre apart;
  // reconstructed, the surface lies on the readings.
  const CliRun synth = levelfuse("synth --shape street --views 12 --resolution 48 --noise 0.003 --json -o " +
                                 path("street"));
  ASSERT_EQ(synth.exitCode, 0) << synth.output;
  const nlohmann::json made = nlohmann::json::parse(synth.output);
  EXPECT_EQ(made["views"], 12);
  EXPECT_EQ(made["projection"], "pinhole");
  EXPECT_NEAR(made["noise_sigma"].get<double>(), 0.0054, 1e-9);
  const CliRun run = levelfuse("reconstruct " + path("street/scans.json") + " --voxel-size 0.03 --json --mesh " +
                               path("street.ply"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const nlohmann::json summary = nlohmann::json::parse(run.output);
  EXPECT_EQ(summary["scans"], 12);
  EXPECT_EQ(summary["levels"], 1) << "depth frames: one grid";
  EXPECT_TRUE(summary["trimmed_unseen"]) << "a scene";
  EXPECT_LT(summary["fit"]["median"].get<double>(), 0.01);
  const CliRun spherical = levelfuse("synth --shape street --scanner spherical -o " + path("lidar"));
  EXPECT_NE(spherical.exitCode, 0);
  EXPECT_NE(spherical.output.find("the street is filmed by depth cameras"), std::string::npos) << spherical.output;
  EXPECT_FALSE(fs::exists(path("lidar")));
}

TEST_F(SceneCli, TheLinearSolutionIsTrimmedToo) {
  const std::string frames = depthFolder();
  const CliRun trimmed = levelfuse("reconstruct " + frames + " --linear --voxel-size 0.05 --json --mesh " +
                                   path("trimmed.ply") + " --preview " + path("room.png"));
  ASSERT_EQ(trimmed.exitCode, 0) << trimmed.output;
  const CliRun closed = levelfuse("reconstruct " + frames + " --linear --voxel-size 0.05 --json --mesh " +
                                  path("closed.ply") + " --no-trim-unseen");
  ASSERT_EQ(closed.exitCode, 0) << closed.output;
  EXPECT_LT(jsonOf(trimmed)["triangles"].get<std::size_t>(), jsonOf(closed)["triangles"].get<std::size_t>() / 2);
  EXPECT_TRUE(fs::exists(path("room.png")));
}

TEST_F(SceneCli, ObjectsAreTrimmedOnlyOnRequest) {
  const CliRun synth = levelfuse("synth --shape sphere --resolution 60 --views 3 -o " + path("scans"));
  ASSERT_EQ(synth.exitCode, 0) << synth.output;
  const std::string common = "reconstruct " + path("scans/scans.json") + " --linear --json --voxel-size 0.05 ";
  const CliRun closed = levelfuse(common + "--mesh " + path("closed.ply") + " -o " + path("s.vdb"));
  ASSERT_EQ(closed.exitCode, 0) << closed.output;
  EXPECT_FALSE(jsonOf(closed)["trimmed_unseen"].get<bool>());
  EXPECT_EQ(openEdges(path("closed.ply")), 0u);
  const CliRun trimmed = levelfuse(common + "--trim-unseen --mesh " + path("trimmed.ply"));
  ASSERT_EQ(trimmed.exitCode, 0) << trimmed.output;
  EXPECT_TRUE(jsonOf(trimmed)["trimmed_unseen"].get<bool>());
  EXPECT_LE(jsonOf(trimmed)["triangles"].get<std::size_t>(), jsonOf(closed)["triangles"].get<std::size_t>());
  const CliRun meshed = levelfuse("mesh --json " + path("s.vdb") + " -o " + path("again.ply"));
  ASSERT_EQ(meshed.exitCode, 0) << meshed.output;
  EXPECT_FALSE(jsonOf(meshed)["trimmed_unseen"].get<bool>());
}

TEST_F(SceneCli, RefusesContradictoryTrimOptionsAndTrimmingWithoutAWeightGrid) {
  const std::string frames = depthFolder();
  const CliRun both = levelfuse("reconstruct " + frames + " --trim-unseen --no-trim-unseen --mesh " + path("m.ply"));
  EXPECT_EQ(both.exitCode, 2) << both.output;
  EXPECT_FALSE(fs::exists(path("m.ply")));
  const CliRun evolve = levelfuse("evolve --max-steps 2 -o " + path("e.vdb"));
  ASSERT_EQ(evolve.exitCode, 0) << evolve.output;
  const CliRun mesh = levelfuse("mesh --trim-unseen " + path("e.vdb") + " -o " + path("e.ply"));
  EXPECT_EQ(mesh.exitCode, 1) << mesh.output;
  EXPECT_NE(mesh.output.find("no weight grid"), std::string::npos) << mesh.output;
  EXPECT_FALSE(fs::exists(path("e.ply")));
}

}  // namespace
}  // namespace levelfuse
