// Inputs that are not files are refused before they are opened; outputs never
// replace an input; messages quote input in short, escaped excerpts.

#include "support/Files.h"
#include "support/InputErrors.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/Ply.h>
#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/io/vdb/VdbFile.h>

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <functional>

namespace levelfuse::io {
namespace {

namespace fs = std::filesystem;

TEST(InputFile, EveryReaderRefusesAFifoWithoutOpeningIt) {
  test::TempDir dir;
  // Opening a FIFO with no writer blocks: a reader that opened one would hang here.
  for (const std::string name : {"scan.ply", "bun.conf", "scans.json", "d.depth.png", "d.depth.pfm",
                                  "camera-intrinsics.txt", "x.vdb"})
    ASSERT_EQ(::mkfifo(dir.path(name).c_str(), 0600), 0) << name;
  const std::vector<std::pair<std::string, std::function<void()>>> readers{
      {"scan.ply", [&] { readPly(dir.path("scan.ply")); }},
      {"bun.conf", [&] { readStanfordConf(dir.path("bun.conf")); }},
      {"bun.conf", [&] { loadScans(dir.path("bun.conf")); }},
      {"scans.json", [&] { loadManifest(dir.path("scans.json")); }},
      {"d.depth.png", [&] { readDepthImage(dir.path("d.depth.png")); }},
      {"d.depth.pfm", [&] { readDepthPfm(dir.path("d.depth.pfm")); }},
      {"camera-intrinsics.txt", [&] { readIntrinsics(dir.path("camera-intrinsics.txt")); }},
      {"x.vdb", [&] { readVdb(dir.path("x.vdb")); }}};
  for (const auto& [name, read] : readers) test::expectInputError(read, dir.path(name), "is a FIFO (named pipe)");
  test::expectInputError([] { requireInputFile("/dev/zero"); }, "/dev/zero", "is a device");
  test::expectInputError([&] { requireInputFile(dir.root().string()); }, dir.root().string(), "is a folder");
  EXPECT_NO_THROW(requireInputFile(dir.root().string(), /*folderToo=*/true));
}

TEST(InputFile, AnOutputThatIsAnInputIsRefusedByIdentity) {
  test::TempDir dir;
  test::writeText(dir.path("scan.ply"), "ply\n");
  fs::create_symlink(dir.path("scan.ply"), dir.path("link.ply"));
  fs::create_hard_link(dir.path("scan.ply"), dir.path("hard.ply"));
  const std::vector<std::string> inputs{dir.path("scan.ply")};
  for (const std::string name : {"scan.ply", "link.ply", "hard.ply"}) {
    try {
      refuseOverwritingInputs({dir.path(name)}, inputs);
      ADD_FAILURE() << name << " was not refused";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("cannot write '" + dir.path(name) + "': it is an input"), std::string::npos)
          << e.what();
    }
  }
  const std::string viaDots = dir.path("../" + dir.root().filename().string() + "/scan.ply");
  EXPECT_THROW(refuseOverwritingInputs({viaDots}, inputs), std::runtime_error);
  test::writeText(dir.path("other.ply"), "ply\n");
  EXPECT_NO_THROW(refuseOverwritingInputs({dir.path("other.ply"), dir.path("new.ply")}, inputs));
}

TEST(InputFile, ReadersRecordTheFilesTheyRead) {
  test::TempDir dir;
  test::writeText(dir.path("recorded.ply"), "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n");
  readPly(dir.path("recorded.ply"));
  const std::vector<std::string> read = inputsRead();
  EXPECT_NE(std::find(read.begin(), read.end(), dir.path("recorded.ply")), read.end());
}

TEST(Quote, IsShortEscapedAndMarksTheCut) {
  EXPECT_EQ(quote("word"), "'word'");
  EXPECT_EQ(quote(std::string("a\nb\x7f", 4)), "'a\\x0ab\\x7f'");
  const std::string quoted = quote(std::string(1 << 20, 'w'));
  EXPECT_EQ(quoted, "'" + std::string(kExcerptBytes, 'w') + "...'");
  EXPECT_EQ(excerpt(std::string(1000, 'e'), 10), "eeeeeeeeee...");
}

/// A huge word where a reader expects a keyword comes back as a short excerpt.
TEST(Quote, ReadersQuoteHugeWordsShortly) {
  test::TempDir dir;
  const std::string huge(1 << 20, 'q');
  test::writeText(dir.path("huge.conf"), huge + " 1 2 3\n");
  test::writeText(dir.path("huge.ply"), "ply\nformat " + huge + " 1.0\nend_header\n");
  test::writeText(dir.path("huge.json"), "{\"scans\": [{\"format\": \"" + huge + "\", \"file\": \"x\"}]}");
  const std::vector<std::pair<std::string, std::function<void()>>> readers{
      {"huge.conf", [&] { readStanfordConf(dir.path("huge.conf")); }},
      {"huge.ply", [&] { readPly(dir.path("huge.ply")); }},
      {"huge.json", [&] { loadManifest(dir.path("huge.json")); }}};
  for (const auto& [name, read] : readers) {
    try {
      read();
      ADD_FAILURE() << name << ": no error";
    } catch (const InputError& e) {
      EXPECT_LT(std::string(e.what()).size(), dir.path(name).size() + 250) << name << ": " << std::string(e.what()).substr(0, 300);
      EXPECT_NE(std::string(e.what()).find("qqq...'"), std::string::npos) << name;
    }
  }
}

}  // namespace
}  // namespace levelfuse::io
