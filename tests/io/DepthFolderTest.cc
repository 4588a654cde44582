// Folders of depth frames in the 7-Scenes layout, and the depth options every
// folder and manifest shares: the depth scale, the frame stride, the maximum depth.

#include "support/DepthFolders.h"
#include "support/Files.h"
#include "support/InputErrors.h"
#include "support/WantedScans.h"

#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/Scans.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace levelfuse::io {
namespace {

using openvdb::Vec3d;
using test::expectInputError;
using test::TempDir;
using test::writeText;

using test::kSmallCamera;

std::vector<test::CameraPose> threeViews() {
  std::vector<test::CameraPose> poses(3);
  for (int i = 0; i < 3; ++i) {
    poses[static_cast<std::size_t>(i)].position = Vec3d(0.1 * i, 0.0, 0.2);
    poses[static_cast<std::size_t>(i)].rotation = test::rotationAbout(Vec3d(0.3 * i, 1.0, 0.0), -20.0 + 15.0 * i);
  }
  return poses;
}

TEST(SevenScenesFolder, FramesOfASyntheticPlaneLandOnIt) {
  TempDir dir;
  test::writeSevenScenesFolder(dir.path("scene"), threeViews(), kSmallCamera, 16, 12, 2.0);
  const std::vector<RangeMap> maps = loadScans(dir.path("scene"));
  ASSERT_EQ(maps.size(), 3u);
  for (const RangeMap& m : maps) {
    EXPECT_EQ(m.validCount(), 16u * 12u) << m.name();
    EXPECT_LT(test::farthestFromPlane(m, 2.0), 2e-3) << m.name();  // millimetre depth steps, stretched by the tilt
  }
  EXPECT_EQ(maps[2].name(), "frame-000002.depth.png");
}

TEST(SevenScenesFolder, AFrameNotWantedIsNotRead) {
  // The loader asks about every frame first, in order, and reads only those
  // wanted: frame 1, without its pose, is never opened.
  TempDir dir;
  test::writeSevenScenesFolder(dir.path("scene"), threeViews(), kSmallCamera, 16, 12, 2.0);
  std::filesystem::remove(dir.path("scene/frame-000001.pose.txt"));
  ScanLoadOptions options;
  std::vector<std::size_t> asked;
  options.wanted = test::everyScanBut(1, asked);
  const std::vector<RangeMap> maps = loadScans(dir.path("scene"), options);
  EXPECT_EQ(asked, (std::vector<std::size_t>{0, 1, 2}));
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps[0].name(), "frame-000000.depth.png");
  EXPECT_EQ(maps[1].name(), "frame-000002.depth.png");
  options.wanted = {};
  expectInputError([&] { loadScans(dir.path("scene"), options); }, dir.path("scene/frame-000001.depth.png"),
                   "no pose beside it");
}

TEST(Manifest, AScanNotWantedIsNeitherReadNorKeptNorHandedOver) {
  TempDir dir;
  test::writeSevenScenesFolder(dir.path("scene"), threeViews(), kSmallCamera, 16, 12, 2.0);
  const std::string manifest = writeScanSet(dir.path("set"), loadScans(dir.path("scene")));
  writeText(dir.path("set/scan0.pfm"), "not a PFM: an entry not wanted is not read");
  ScanLoadOptions options;
  options.wanted = [](std::size_t scan) { return scan != 0; };
  const std::vector<RangeMap> kept = loadScans(manifest, options);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0].name(), "scan1.pfm");
  std::vector<std::string> taken;
  options.take = [&](RangeMap&& map) { taken.push_back(map.name()); };
  EXPECT_TRUE(loadScans(manifest, options).empty());
  EXPECT_EQ(taken, (std::vector<std::string>{"scan1.pfm", "scan2.pfm"}));
}

TEST(SevenScenesFolder, StrideMaximumDepthAndScale) {
  TempDir dir;
  test::writeSevenScenesFolder(dir.path("scene"), threeViews(), kSmallCamera, 16, 12, 2.0);
  ScanLoadOptions options;
  options.frameStride = 2;
  const std::vector<RangeMap> strided = loadScans(dir.path("scene"), options);
  ASSERT_EQ(strided.size(), 2u);
  EXPECT_EQ(strided[1].name(), "frame-000002.depth.png");

  options = ScanLoadOptions();
  options.maxDepth = 1.9;  // the first view sees the plane from about 1.6 to 2.5 m
  const RangeMap near = loadScans(dir.path("scene"), options)[0];
  EXPECT_GT(near.validCount(), 0u);
  EXPECT_LT(near.validCount(), 16u * 12u);
  for (int v = 0; v < near.height(); ++v)
    for (int u = 0; u < near.width(); ++u)
      if (near.valid(u, v)) {
        EXPECT_LE(near.reading(u, v), 1.9f);
      }

  options = ScanLoadOptions();
  options.depthScale = 0.002;  // the user's: twice the millimetres of the convention
  const RangeMap doubled = loadScans(dir.path("scene"), options)[0];
  EXPECT_NEAR(doubled.reading(7, 5), 2.0 * loadScans(dir.path("scene"))[0].reading(7, 5), 1e-5);

  options = ScanLoadOptions();
  options.maxDepth = -1.0;
  expectInputError([&] { loadScans(dir.path("scene"), options); }, dir.path("scene"),
                   "the maximum depth must be positive");
  options = ScanLoadOptions();
  options.depthScale = std::nan("");
  expectInputError([&] { loadScans(dir.path("scene"), options); }, dir.path("scene"), "the depth scale must be positive");
}

TEST(ManifestDepthEntries, MaximumDepthFromTheEntryOrTheDefaults) {
  TempDir dir;
  test::writeSevenScenesFolder(dir.path("scene"), threeViews(), kSmallCamera, 16, 12, 2.0);
  writeText(dir.path("m.json"), R"({ "scans": [
    { "format": "depth-png", "file": "scene/frame-000000.depth.png", "intrinsics_file": "scene/camera-intrinsics.txt",
      "pose_file": "scene/frame-000000.pose.txt" },
    { "format": "depth-png", "file": "scene/frame-000000.depth.png", "intrinsics_file": "scene/camera-intrinsics.txt",
      "pose_file": "scene/frame-000000.pose.txt", "max_depth": 1.9 } ] })");
  std::vector<RangeMap> maps = loadManifest(dir.path("m.json"));
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps[0].validCount(), 16u * 12u);
  const std::size_t nearer = maps[1].validCount();
  EXPECT_LT(nearer, 16u * 12u);
  ScanLoadOptions defaults;
  defaults.maxDepth = 1.9;  // the command line's --max-depth: for entries without their own
  EXPECT_EQ(loadManifest(dir.path("m.json"), defaults)[0].validCount(), nearer);
  writeText(dir.path("bad.json"), R"({ "scans": [
    { "format": "depth-png", "file": "scene/frame-000000.depth.png", "intrinsics_file": "scene/camera-intrinsics.txt",
      "pose_file": "scene/frame-000000.pose.txt", "max_depth": 0 } ] })");
  expectInputError([&] { loadManifest(dir.path("bad.json")); }, dir.path("bad.json"),
                   "scans[0]: 'max_depth' must be positive");
}

TEST(ManifestDepthEntries, ATumFolder) {
  TempDir dir;
  test::TumFixture f;
  for (int i = 0; i < 4; ++i) f.poses.push_back({10.0 + 0.1 * i, test::CameraPose{Vec3d(0.05 * i, 0, 0), {0, 0, 0, 1}}});
  f.frameTimes = {10.0, 10.1, 10.2, 10.3};
  test::writeTumFolder(dir.path("tum"), f);
  writeText(dir.path("m.json"), R"({ "scans": [ { "format": "tum", "folder": "tum", "frame_stride": 2,
                                                   "max_depth": 5 } ] })");
  const std::vector<RangeMap> maps = loadManifest(dir.path("m.json"));
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_NEAR(maps[1].scannerPosition().x(), 0.1, 1e-9);
  EXPECT_NEAR(maps[1].reading(7, 5), 2.0, 1e-3);
  // Taken as read, and of those wanted alone: the manifest's order and numbers, the folder's frames among them.
  writeText(dir.path("m.json"), R"({ "scans": [ { "format": "tum", "folder": "tum" },
    { "format": "depth-png", "file": "tum/depth/10.000000.png", "intrinsics": {"fx": 525, "fy": 525, "cx": 319.5, "cy": 239.5},
      "pose": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] } ] })");
  ScanLoadOptions options;
  std::vector<std::size_t> asked;
  options.wanted = [&](std::size_t scan) {
    asked.push_back(scan);
    return scan % 2 == 0;
  };
  std::vector<std::string> taken;
  options.take = [&](RangeMap&& map) { taken.push_back(map.name()); };
  EXPECT_TRUE(loadScans(dir.path("m.json"), options).empty());
  EXPECT_EQ(asked, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  ASSERT_EQ(taken.size(), 3u);
  EXPECT_EQ(taken[2], "10.000000.png") << "the entry after the folder's frames comes after them";
  writeText(dir.path("m.json"), R"({ "scans": [ { "format": "tum", "folder": "tum", "frame_stride": 0.5 } ] })");
  expectInputError([&] { loadManifest(dir.path("m.json")); }, dir.path("m.json"),
                   "scans[0]: 'frame_stride' must be a whole number, 1 to 1000000");
  writeText(dir.path("m.json"), R"({ "scans": [ { "format": "tum", "folder": "nowhere" } ] })");
  expectInputError([&] { loadManifest(dir.path("m.json")); }, dir.path("m.json"), "scans[0]: 'folder': no such folder");
}

}  // namespace
}  // namespace levelfuse::io
