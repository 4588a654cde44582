// Output files appear whole or not at all, and never replace what is not a file.

#include "support/Files.h"

#include <levelfuse/io/AtomicWrite.h>

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

}  // namespace
}  // namespace levelfuse::io
