// Output files appear whole or not at all, and never replace what is not a file.

#include "support/Files.h"
#include "support/SmallDisk.h"
#include "support/TestSupport.h"

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/io/outputs/MeshFile.h>
#include <levelfuse/io/outputs/Preview.h>
#include <levelfuse/io/vdb/VdbFile.h>
#include <levelfuse/levelset/Mesh.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace levelfuse::io {
namespace {

namespace fs = std::filesystem;

std::string contents(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(AtomicWrite, ReplacesAFileOnlyWhenTheWriteSucceeds) {
  test::TempDir dir;
  const std::string target = dir.path("out.txt");
  writeAtomically(target, [](const std::string& temporary) { std::ofstream(temporary) << "first"; });
  EXPECT_EQ(contents(target), "first");
  EXPECT_THROW(writeAtomically(target,
                               [](const std::string& temporary) {
                                 std::ofstream(temporary) << "half";
                                 throw std::runtime_error("disk full");
                               }),
               std::runtime_error);
  EXPECT_EQ(contents(target), "first");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.root()), fs::directory_iterator()), 1);  // no temporary left
}

TEST(AtomicWrite, NeverReplacesWhatIsNotARegularFile) {
  test::TempDir dir;
  fs::create_directory(dir.path("folder"));
  bool called = false;
  const auto write = [&](const std::string&) { called = true; };
  EXPECT_THROW(writeAtomically(dir.path("folder"), write), std::runtime_error);
  EXPECT_TRUE(fs::is_directory(dir.path("folder")));
  EXPECT_THROW(writeAtomically("/dev/null", write), std::runtime_error);
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_FALSE(called);
}

std::size_t filesIn(const fs::path& folder) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(folder), fs::directory_iterator()));
}

TEST(OutputSet, CommitsEveryFileOrNone) {
  test::TempDir dir;
  std::ofstream(dir.path("a.txt")) << "old a";
  {
    OutputSet outputs;
    outputs.add(dir.path("a.txt"), [](const std::string& temporary) { std::ofstream(temporary) << "new a"; });
    EXPECT_THROW(outputs.add(dir.path("b.txt"),
                             [](const std::string& temporary) {
                               std::ofstream(temporary) << "half";
                               throw std::runtime_error("disk full");
                             }),
                 std::runtime_error);
    EXPECT_EQ(contents(dir.path("a.txt")), "old a");  // nothing renamed before commit
  }  // abandoned: its temporaries go
  EXPECT_EQ(contents(dir.path("a.txt")), "old a");
  EXPECT_EQ(filesIn(dir.root()), 1u);

  OutputSet outputs;
  outputs.add(dir.path("a.txt"), [](const std::string& temporary) { std::ofstream(temporary) << "new a"; });
  outputs.add(dir.path("b.txt"), [](const std::string& temporary) { std::ofstream(temporary) << "new b"; });
  EXPECT_THROW(outputs.add(dir.path("a.txt"), [](const std::string&) {}), std::runtime_error);  // twice
  outputs.commit();
  EXPECT_EQ(contents(dir.path("a.txt")), "new a");
  EXPECT_EQ(contents(dir.path("b.txt")), "new b");
  EXPECT_EQ(filesIn(dir.root()), 2u);
}

TEST(OutputSet, ClosedStreamsReportAFullDisk) {
  std::ofstream full("/dev/full");
  ASSERT_TRUE(full) << "no /dev/full";
  full << std::string(1 << 16, 'x');
  EXPECT_THROW(closeChecked(full), std::runtime_error);
}

/// Every writer, on a full disk: throws naming the file, leaves no partial
/// file, and the file it would have replaced keeps its content.
TEST(OutputSet, WritersOnAFullDiskFailAndKeepTheOldFile) {
  test::SmallDisk disk;
  if (!disk.mounted()) GTEST_SKIP() << disk.reason();
  const auto sphere = test::makeSphere(40.0, openvdb::Vec3d(0.0), 0.025);
  const TriangleMesh mesh = meshFromLevelSet(*sphere);
  const std::vector<std::pair<std::string, std::function<void(const std::string&)>>> writers{
      {"s.vdb", [&](const std::string& path) { writeVdb(path, {sphere}); }},
      {"s.ply", [&](const std::string& path) { writeMesh(path, mesh); }},
      {"s.obj", [&](const std::string& path) { writeMesh(path, mesh); }},
      {"s.png", [&](const std::string& path) { writePreviewPng(*sphere, path); }}};
  for (const auto& [name, write] : writers) std::ofstream(disk.path(name)) << "old";
  disk.fill();
  const std::size_t files = disk.fileCount();
  for (const auto& [name, write] : writers) {
    try {
      write(disk.path(name));
      ADD_FAILURE() << name << ": written on a full disk";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(disk.path(name)), std::string::npos) << e.what();
    }
    EXPECT_EQ(contents(disk.path(name)), "old") << name;
    EXPECT_EQ(disk.fileCount(), files) << name << ": a temporary was left";
  }
}

}  // namespace
}  // namespace levelfuse::io
