// Every reader of a list of scans or frames says how far it has got, and
// stops when asked to.

#include "support/DepthFolders.h"
#include "support/Files.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/Scans.h>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse::io {
namespace {

using openvdb::Vec3d;
using test::TempDir;
using Reports = std::vector<std::pair<std::size_t, std::size_t>>;

using test::kSmallCamera;

/// `count` cameras at z = 0 along x, looking at the plane z = 2.
std::vector<test::CameraPose> poses(int count) {
  std::vector<test::CameraPose> out(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) out[static_cast<std::size_t>(i)].position = Vec3d(0.05 * i, 0.0, 0.0);
  return out;
}

test::TumFixture tumFrames(int count) {
  test::TumFixture f;
  for (int i = 0; i < count; ++i) {
    f.poses.push_back({1.0 + i, test::CameraPose{Vec3d(0.05 * i, 0.0, 0.0), {0.0, 0.0, 0.0, 1.0}}});
    f.frameTimes.push_back(1.0 + i);
  }
  return f;
}

Reports loadReporting(const std::string& path, int stride = 1) {
  Reports reports;
  ScanLoadOptions options;
  options.frameStride = stride;
  options.progress = [&](std::size_t read, std::size_t total) { reports.emplace_back(read, total); };
  loadScans(path, options);
  return reports;
}

TEST(LoadProgress, SevenScenesFoldersReportEachFrameOfTheStride) {
  TempDir dir;
  test::writeSevenScenesFolder(dir.path("scene"), poses(5), kSmallCamera, 16, 12, 2.0);
  EXPECT_EQ(loadReporting(dir.path("scene"), 2), (Reports{{1, 3}, {2, 3}, {3, 3}}));
  EXPECT_EQ(loadReporting(dir.path("scene")), (Reports{{1, 5}, {2, 5}, {3, 5}, {4, 5}, {5, 5}}));
}

TEST(LoadProgress, TumFoldersReportEachFrame) {
  TempDir dir;
  test::writeTumFolder(dir.path("tum"), tumFrames(4));
  EXPECT_EQ(loadReporting(dir.path("tum")), (Reports{{1, 4}, {2, 4}, {3, 4}, {4, 4}}));
  EXPECT_EQ(loadReporting(dir.path("tum"), 3), (Reports{{1, 2}, {2, 2}}));
}

TEST(LoadProgress, ScansAreHandedOverAsTheyAreReadWhenTaken) {
  TempDir dir;
  test::writeSevenScenesFolder(dir.path("scene"), poses(5), kSmallCamera, 16, 12, 2.0);
  test::writeTumFolder(dir.path("tum"), tumFrames(4));
  for (const std::string& folder : {dir.path("scene"), dir.path("tum")}) {
    const std::vector<RangeMap> held = loadScans(folder);
    std::vector<std::string> taken;
    Reports reports;
    ScanLoadOptions options;
    // Each frame is handed over before the next is read: the progress report follows it.
    options.take = [&](RangeMap&& frame) {
      EXPECT_EQ(reports.size(), taken.size());
      taken.push_back(frame.name());
    };
    options.progress = [&](std::size_t read, std::size_t total) { reports.emplace_back(read, total); };
    EXPECT_TRUE(loadScans(folder, options).empty());
    ASSERT_EQ(taken.size(), held.size()) << folder;
    for (std::size_t i = 0; i < held.size(); ++i) EXPECT_EQ(taken[i], held[i].name());
  }
  // A manifest's scans, read together, are handed over too.
  const std::string manifest = writeScanSet(dir.path("set"), loadScans(dir.path("scene")));
  std::size_t taken = 0;
  ScanLoadOptions options;
  options.take = [&](RangeMap&&) { ++taken; };
  EXPECT_TRUE(loadScans(manifest, options).empty());
  EXPECT_EQ(taken, 5u);
}

TEST(LoadProgress, ManifestsReportTheirEntries) {
  TempDir dir;
  test::writeSevenScenesFolder(dir.path("scene"), poses(3), kSmallCamera, 16, 12, 2.0);
  const std::string manifest = writeScanSet(dir.path("set"), loadScans(dir.path("scene")));
  EXPECT_EQ(loadReporting(manifest), (Reports{{1, 3}, {2, 3}, {3, 3}}));
}

TEST(LoadProgress, FramesReadTogetherArriveInOrderAndTheFirstBadOneIsNamed) {
  TempDir dir;
  test::writeSevenScenesFolder(dir.path("scene"), poses(11), kSmallCamera, 16, 12, 2.0);
  for (const int threads : {1, 2, 5}) {
    SCOPED_TRACE(threads);
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    std::vector<std::string> names;
    ScanLoadOptions options;
    options.take = [&](RangeMap&& map) { names.push_back(map.name()); };
    loadScans(dir.path("scene"), options);
    ASSERT_EQ(names.size(), 11u);
    for (std::size_t i = 0; i < names.size(); ++i)
      EXPECT_EQ(names[i], "frame-" + std::string(i < 10 ? "00000" : "0000") + std::to_string(i) + ".depth.png");
  }
  // Frames 6 and 9 lose their poses: frame 6 is named whatever the threads.
  std::filesystem::remove(dir.path("scene/frame-000009.pose.txt"));
  std::filesystem::remove(dir.path("scene/frame-000006.pose.txt"));
  for (const int threads : {1, 2, 5}) {
    SCOPED_TRACE(threads);
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    try {
      loadScans(dir.path("scene"));
      ADD_FAILURE() << "frames without poses were read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("frame-000006.depth.png: no pose beside it"), std::string::npos)
          << e.what();
    }
  }
}

TEST(LoadProgress, ATumFolderStopsWhenAsked) {
  TempDir dir;
  test::writeTumFolder(dir.path("tum"), tumFrames(4));
  ScanLoadOptions options;
  std::size_t read = 0;
  options.progress = [&](std::size_t n, std::size_t) { read = n; };
  options.interrupter = [&] { return read >= 2; };
  EXPECT_THROW(loadScans(dir.path("tum"), options), Interrupted);
  EXPECT_EQ(read, 2u);
}

}  // namespace
}  // namespace levelfuse::io
