// levelfuse: the command-line converter. Thin: the work is in the library.

#include "Cancellation.h"
#include "Commands.h"
#include "FlagHints.h"
#include "Job.h"
#include "Support.h"

#include <levelfuse/Version.h>
#include <levelfuse/core/Interrupter.h>
#include <levelfuse/io/InputError.h>

#include <openvdb/openvdb.h>
#include <tbb/version.h>

#include <cstdlib>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <vector>

namespace {

/// "levelfuse <command>", for the messages of the running command.
std::string gCommandName = "levelfuse";

/// " (rank r of n)" in an MPI job of more than one rank, else nothing.
std::string jobPlace() {
  const levelfuse::SlabTeam* team = levelfuse::cli::jobTeam();
  return team ? " (rank " + std::to_string(team->rank()) + " of " + std::to_string(team->size()) + ")" : "";
}

void reportOutOfMemory() {
  // One write per line, so that the lines of an MPI job's ranks do not interleave.
  std::cerr << gCommandName + ": error: out of memory while " + levelfuse::cli::currentPhase() + jobPlace() +
                   "; nothing written (use a larger voxel size, fewer scans, or a machine with more memory)\n";
}

/// Ends the process after a failure: in an MPI job, every rank with it.
int failed(int exitCode) {
  levelfuse::cli::abortJobIfShared(exitCode);
  levelfuse::cli::leaveJob();
  return exitCode;
}

/// Where an exception cannot be caught (a destructor that allocates while the
/// stack unwinds, a library's noexcept function, a worker thread that cannot
/// start), std::terminate is called: a bad_alloc or another error there still
/// ends in the one-line error and exit code 1.
[[noreturn]] void onTerminate() {
  if (const std::exception_ptr pending = std::current_exception()) {
    try {
      std::rethrow_exception(pending);
    } catch (const std::bad_alloc&) {
      reportOutOfMemory();
    } catch (const std::exception& e) {
      std::cerr << gCommandName + ": error: " + levelfuse::io::excerpt(e.what()) + jobPlace() + "\n";
    } catch (...) {
      std::cerr << gCommandName + ": error: an unknown failure" + jobPlace() + "\n";
    }
    levelfuse::cli::abortJobIfShared(levelfuse::cli::kExitFailure);
    std::_Exit(levelfuse::cli::kExitFailure);
  }
  std::abort();
}

}  // namespace

namespace {

int runCommand(int argc, char** argv) {
  using namespace levelfuse::cli;
  CLI::App app{"levelfuse: surfaces from range maps with sparse-field level sets on OpenVDB"};
  app.require_subcommand(1);
  app.set_version_flag("--version",
                       std::string("levelfuse ") + levelfuse::version() + " (OpenVDB " +
                           openvdb::getLibraryVersionString() + ", oneTBB " + TBB_VERSION_STRING + ")");
  app.footer(
      "Run 'levelfuse <command> --help' for a command's options and examples.\n"
      "Exit codes: 0 success, 1 failure (bad input, I/O), 2 usage error, 130 interrupted.");

  const std::vector<Command> commands{addReconstructCommand(app), addSynthCommand(app), addInfoCommand(app),
                                      addMeshCommand(app), addEvolveCommand(app)};

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return leadsTheJob() ? app.exit(e) : kExitSuccess;
  } catch (const CLI::CallForAllHelp& e) {
    return leadsTheJob() ? app.exit(e) : kExitSuccess;
  } catch (const CLI::CallForVersion& e) {
    return leadsTheJob() ? app.exit(e) : kExitSuccess;
  } catch (const CLI::ParseError& e) {
    // Every rank of a job parses the same arguments: the first says what is wrong.
    if (leadsTheJob()) app.exit(e);
    return kExitUsage;
  }

  openvdb::initialize();
  for (const Command& command : commands) {
    if (!command.app->parsed()) continue;
    const std::string name = "levelfuse " + command.app->get_name();
    gCommandName = name;
    // Under mpirun, reconstruct shares its work between the ranks; the other
    // commands run on the first rank alone.
    if (command.app->get_name() != "reconstruct" && !leadsTheJob()) return kExitSuccess;
    try {
      checkCancellation();
      return command.run();
    } catch (const levelfuse::Interrupted&) {
      std::cerr << name + ": interrupted while " + currentPhase() + jobPlace() + "; nothing written\n";
      return failed(kExitCancelled);
    } catch (const std::bad_alloc&) {
      reportOutOfMemory();
      return failed(kExitFailure);
    } catch (const std::exception& e) {
      // Readers quote short excerpts; the cut is the last guard for a third party's message.
      std::cerr << name + ": error: " + withFlagHints(levelfuse::io::excerpt(e.what(), 2000)) + jobPlace() + "\n";
      return failed(kExitFailure);
    }
  }
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  levelfuse::cli::installCancellationHandlers();
  std::set_terminate(onTerminate);
  levelfuse::cli::joinJobIfLaunched(argc, argv);
  const int exitCode = runCommand(argc, argv);
  levelfuse::cli::leaveJob();
  return exitCode;
}
