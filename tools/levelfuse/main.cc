// levelfuse: the command-line converter. Thin: the work is in the library.

#include "Cancellation.h"
#include "Commands.h"
#include "Support.h"

#include <levelfuse/Version.h>

#include <openvdb/openvdb.h>
#include <tbb/version.h>

#include <iostream>
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
    try {
      return command.run();
    } catch (const std::exception& e) {
      std::cerr << "levelfuse " << command.app->get_name() << ": error: " << printable(e.what()) << "\n";
      return kExitFailure;
    }
  }
  return kExitUsage;
}
