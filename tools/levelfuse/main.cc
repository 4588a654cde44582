// levelfuse: the command-line converter. Thin: the work is in the library.

#include "Cancellation.h"
#include "Commands.h"
#include "Support.h"

#include <levelfuse/Version.h>
#include <levelfuse/core/Interrupter.h>
#include <levelfuse/io/InputError.h>

#include <openvdb/openvdb.h>
#include <tbb/version.h>

#include <iostream>
#include <new>
#include <string>
#include <vector>

int main(int argc, char** argv) {
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
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitUsage;
  }

  openvdb::initialize();
  installCancellationHandlers();
  for (const Command& command : commands) {
    if (!command.app->parsed()) continue;
    const std::string name = "levelfuse " + command.app->get_name();
    try {
      return command.run();
    } catch (const levelfuse::Interrupted&) {
      std::cerr << name << ": interrupted while " << currentPhase() << "; nothing written\n";
      return kExitCancelled;
    } catch (const std::bad_alloc&) {
      std::cerr << name << ": error: out of memory while " << currentPhase()
                << "; nothing written (use a larger voxel size, fewer scans, or a machine with more memory)\n";
      return kExitFailure;
    } catch (const std::exception& e) {
      // Readers quote short excerpts; the cut is the last guard for a third party's message.
      std::cerr << name << ": error: " << levelfuse::io::excerpt(e.what(), 2000) << "\n";
      return kExitFailure;
    }
  }
  return kExitUsage;
}
