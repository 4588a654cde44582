// levelfuse CLI: the subcommands and the exit codes they share.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>

namespace levelfuse::cli {

/// Exit codes, documented in the README.
enum ExitCode : int {
  kExitSuccess = 0,
  kExitFailure = 1,    ///< the command could not do its job (bad input file, I/O error, ...)
  kExitUsage = 2,      ///< the command line is wrong
  kExitCancelled = 130 ///< interrupted by SIGINT/SIGTERM; no output was written
};

/// A registered subcommand and the function that runs it once parsed.
struct Command {
  CLI::App* app;
  std::function<int()> run;
};

/// Register the subcommands on `app`.
Command addReconstructCommand(CLI::App& app);
Command addSynthCommand(CLI::App& app);
Command addInfoCommand(CLI::App& app);
Command addMeshCommand(CLI::App& app);
Command addEvolveCommand(CLI::App& app);

}  // namespace levelfuse::cli
