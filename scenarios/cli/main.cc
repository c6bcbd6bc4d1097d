// The trav command line: `trav run`, `trav scan`, `trav terrain`, `trav calibrate`, `trav eval`,
// `trav batch`, `trav tune`; each subcommand in its own file. Only this executable prints.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/input_error.h"
#include "common/logging.h"
#include "scenarios/cli/cli.h"
#include "scenarios/run/provenance.h"

namespace trav::scenarios::cli {
namespace {

// The command line as typed, for the report.
std::string CommandLine(int argc, char** argv) {
  std::string line = "trav";
  for (int i = 1; i < argc; ++i) line += std::string(" ") + argv[i];
  return line;
}

// Runs the parsed command; maps what it throws to the exit codes: bad input 2, internal error 3.
int RunParsed(const std::vector<Command>& commands) {
  try {
    for (const Command& command : commands) {
      if (command.parser->parsed()) return command.run();
    }
    return kExitInternalError;
  } catch (const common::InputError& e) {
    std::fprintf(stderr, "trav: error: %s\n", common::Excerpt(e.what(), 1000).c_str());
    return kExitBadInput;
  } catch (const std::filesystem::filesystem_error& e) {
    // the machine's answer to a path of the user's: no permission, no space, not a folder
    std::fprintf(stderr, "trav: error: %s\n", common::Excerpt(e.what(), 2000).c_str());
    return kExitBadInput;
  } catch (const nlohmann::json::exception& e) {
    // trav reads JSON only from its own folders and job files: one edited or cut short by hand,
    // or a name that is not UTF-8, is bad input
    std::fprintf(stderr, "trav: error: malformed JSON in a trav folder or file: %s\n",
                 common::Excerpt(e.what(), 400).c_str());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "trav: internal error: %s\n", e.what());
    return kExitInternalError;
  }
}

int Main(int argc, char** argv) {
  CLI::App app{"trav: physics-simulated navigation testbed for the Scout Mini on uneven terrain"};
  app.require_subcommand(1);
  // options of trav itself (-v) are accepted after the subcommand too
  app.fallthrough();
  app.set_version_flag("--version", VersionText());
  app.set_help_all_flag("--help-all", "Help for every command");
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose,
               "Log debug messages (MuJoCo warnings as they happen) to stderr");
  const std::vector<Command> commands = {
      AddRunCommand(&app),       AddScanCommand(&app),
      AddTerrainCommand(&app),   AddPatternCommand(&app),
      AddCalibrateCommand(&app), AddTruthCheckCommand(&app),
      AddUrdfCommand(&app),      AddEvalCommand(&app, CommandLine(argc, argv)),
      AddBatchCommand(&app),     AddTuneCommand(&app),
      AddJobTaskCommand(&app),   AddEvalSceneCommand(&app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitExpected : kExitBadInput;
  }
  if (verbose) common::SetLogLevel(common::LogLevel::kDebug);
  return RunParsed(commands);
}

}  // namespace
}  // namespace trav::scenarios::cli

int main(int argc, char** argv) { return trav::scenarios::cli::Main(argc, argv); }
