// Running the levelfuse command-line converter as a user runs it.
#pragma once

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>

namespace levelfuse {

namespace fs = std::filesystem;

struct CliRun {
  int exitCode = -1;
  std::string output;  // stdout and stderr
};

/// Runs `levelfuse <arguments>`, with `environment` ("NAME=value ...") added to its environment.
inline CliRun levelfuse(const std::string& arguments, const std::string& environment = "") {
  CliRun run;
  const std::string command =
      (environment.empty() ? "" : "env " + environment + " ") + std::string(LEVELFUSE_CLI) + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return run;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof(buffer), pipe)) run.output.append(buffer, n);
  const int status = pclose(pipe);
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

/// A run's output as JSON (a --json summary); a test failure if it is not.
inline nlohmann::json jsonOf(const CliRun& run) {
  try {
    return nlohmann::json::parse(run.output);
  } catch (const std::exception&) {
    ADD_FAILURE() << "not JSON:\n" << run.output;
    return nlohmann::json::object();
  }
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    // The converter keeps a signal it was started with ignored; the tests that
    // interrupt it need the default actions, however the test runner was started.
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    mDir = fs::temp_directory_path() / uniqueDirectoryName();
    fs::remove_all(mDir);
    fs::create_directories(mDir);
  }
  void TearDown() override { fs::remove_all(mDir); }
  std::string path(const std::string& name) const { return (mDir / name).string(); }
  std::size_t filesInDir() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(mDir), fs::directory_iterator()));
  }
  fs::path mDir;

 private:
  /// Suite, test and process: tests of different suites may share a name and run at once under ctest -j.
  static std::string uniqueDirectoryName() {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string("levelfuse_cli_") + test->test_suite_name() + "." + test->name() + "_" +
                       std::to_string(::getpid());
    for (char& c : name)
      if (c == '/') c = '_';
    return name;
  }
};

}  // namespace levelfuse
