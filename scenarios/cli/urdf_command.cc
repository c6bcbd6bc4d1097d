// trav urdf: the scenario's robot file (robot.model) as a URDF for ROS tools.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "common/input_error.h"
#include "scenarios/cli/cli.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios::cli {
namespace {

struct UrdfFlags {
  ScenarioOptions scenario;  // the scenario and --set only
  std::string file;          // empty: standard output
  bool overwrite{false};
};

int Urdf(const UrdfFlags& flags) {
  // trav never replaces a file it was not told to
  if (!flags.file.empty() && std::filesystem::exists(flags.file) && !flags.overwrite) {
    throw common::InputError(flags.file, "", "exists; pass --overwrite to replace it");
  }
  const Scenario scenario = ResolveScenario(flags.scenario, std::nullopt);
  const std::string urdf = RobotUrdfOf(ExistingRobotModel(scenario));
  if (flags.file.empty()) {
    std::fputs(urdf.c_str(), stdout);
  } else {
    WriteTextFileAtomically(flags.file, urdf);
    std::printf("urdf: %s\n", flags.file.c_str());
  }
  return kExitExpected;
}

}  // namespace

Command AddUrdfCommand(CLI::App* app) {
  auto flags = std::make_shared<UrdfFlags>();
  CLI::App* urdf = app->add_subcommand(
      "urdf", "Print (or write with --out) the scenario's robot, robot.model, as a URDF");
  urdf->add_option("scenario", flags->scenario.path,
                   "Scenario YAML file (default: the built-in scenario's robot, the Scout Mini)");
  urdf->add_option("--out", flags->file, "Write the URDF to this file instead of printing it");
  urdf->add_flag("--overwrite", flags->overwrite, "Replace the file --out names if it exists");
  AddSetOption(urdf, &flags->scenario.sets, "the scenario");
  return {urdf, [flags] { return Urdf(*flags); }};
}

}  // namespace trav::scenarios::cli
