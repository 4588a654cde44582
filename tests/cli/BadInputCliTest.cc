// Every bad scan set of the corpus (tests/data/bad: .conf files, manifests,
// PTX files and folders of depth frames) and every bad .vdb file given to the
// converter as a user gives it: one line that names a file and the problem,
// exit code 1, and no output file.

#include "CliSupport.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <initializer_list>
#include <string>
#include <vector>

namespace levelfuse {
namespace {

/// The entries of the corpus's folders of these kinds, sorted.
std::vector<std::string> corpusFiles(std::initializer_list<const char*> kinds) {
  std::vector<std::string> files;
  for (const char* kind : kinds)
    for (const auto& entry : fs::directory_iterator(fs::path(LEVELFUSE_TEST_DATA_DIR) / "bad" / kind))
      files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

/// Files for .conf, manifests and PTX; folders of depth frames for 7-Scenes and TUM RGB-D; scans that
/// read well but that no reconstruction can take.
std::vector<std::string> badScanSets() {
  return corpusFiles({"conf", "manifest", "7scenes", "tum", "ptx", "reconstruct"});
}

std::vector<std::string> badVdbFiles() { return corpusFiles({"vdb"}); }

/// One line that names a file of the corpus and the problem, exit code 1, no output.
void expectOneLineErrorAndNoOutput(const CliRun& run, const std::string& command, const fs::path& outputs) {
  EXPECT_EQ(run.exitCode, 1) << run.output;
  ASSERT_FALSE(run.output.empty());
  const std::string prefix = "levelfuse " + command + ": error: ";
  EXPECT_EQ(run.output.rfind(prefix, 0), 0u) << run.output;
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
  // It names the file, or the file of the corpus that it refers to.
  EXPECT_NE(run.output.find(fs::path(LEVELFUSE_TEST_DATA_DIR).string() + "/bad/"), std::string::npos) << run.output;
  // Printable: what a file held is never echoed raw to the terminal.
  EXPECT_TRUE(std::none_of(run.output.begin(), run.output.end() - 1, [](char c) {
    const auto byte = static_cast<unsigned char>(c);
    return byte < 0x20 || byte == 0x7f;
  })) << run.output;
  EXPECT_TRUE(fs::is_empty(outputs)) << "an output was written";
}

std::string corpusTestName(const ::testing::TestParamInfo<std::string>& param) {
  const fs::path file(param.param);
  std::string name = file.parent_path().filename().string() + "_" + file.stem().string();
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

class BadInputCli : public Cli, public ::testing::WithParamInterface<std::string> {};

TEST_P(BadInputCli, FailsWithOneLineAndWritesNothing) {
  const std::string& input = GetParam();
  const bool readsWell = fs::path(input).parent_path().filename() == "reconstruct";
  for (const std::string command : {"reconstruct", "info"}) {
    SCOPED_TRACE(command);
    if (command == "info" && readsWell) continue;
    const std::string outputs =
        command == "info" ? "" : " -o " + path("out.vdb") + " --mesh " + path("out.ply") + " --preview " + path("out.png");
    expectOneLineErrorAndNoOutput(levelfuse(command + " '" + input + "'" + outputs), command, mDir);
  }
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadInputCli, ::testing::ValuesIn(badScanSets()), corpusTestName);

class BadVdbCli : public Cli, public ::testing::WithParamInterface<std::string> {};

TEST_P(BadVdbCli, InfoAndMeshFailWithOneLineAndWriteNothing) {
  const std::string& input = GetParam();
  expectOneLineErrorAndNoOutput(levelfuse("info '" + input + "'"), "info", mDir);
  expectOneLineErrorAndNoOutput(levelfuse("mesh '" + input + "' -o " + path("out.ply")), "mesh", mDir);
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadVdbCli, ::testing::ValuesIn(badVdbFiles()), corpusTestName);

}  // namespace
}  // namespace levelfuse
