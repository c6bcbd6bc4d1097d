// trav truth-check: the physical ground truth against what the robot does in MuJoCo.
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/enum_names.h"
#include "common/input_error.h"
#include "scenarios/cli/cli.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/truth_check.h"

namespace trav::scenarios::cli {
namespace {

// The agreement every terrain type must reach for the check to pass (exit 0).
constexpr double kRequiredAgreement = 0.9;

struct TruthCheckFlags {
  ScenarioOptions scenario;
  std::vector<std::string> terrains{"hilly", "forest", "ruin", "road", "indoor"};
  TruthCheckOptions check;
};

int TruthCheck(const TruthCheckFlags& flags) {
  const Scenario scenario = ResolveScenario(flags.scenario, std::nullopt);
  const std::string model = ExistingRobotModel(scenario);
  common::RequireValue(flags.check.samples >= 2 && flags.check.samples <= 100000, "--samples",
                       flags.check.samples, "must be in [2, 100000]");
  std::vector<sim::TerrainType> types;
  for (const std::string& name : flags.terrains) {
    const std::optional<sim::TerrainType> type = common::EnumFromName<sim::TerrainType>(name);
    if (!type) {
      throw common::InputError(
          "--terrains", name,
          "unknown terrain type (expected " + common::EnumNameList<sim::TerrainType>() + ")");
    }
    types.push_back(*type);
  }
  std::vector<std::pair<std::string, std::vector<TruthCheckSample>>> runs;
  bool passed = true;
  std::printf("%-8s %8s %12s %10s %12s %10s\n", "terrain", "samples", "predicted ok", "agreement",
              "ok & crossed", "not & not");
  for (std::size_t i = 0; i < types.size(); ++i) {
    TruthCheckOptions options = flags.check;
    // the scenario's terrain seed (--seed) and parameters (--set terrain.parameters...)
    options.terrain = scenario.terrain;
    options.terrain.type = types[i];
    runs.emplace_back(flags.terrains[i], CheckPhysicalTruth(options, model, scenario.skid_steer,
                                                            scenario.ground_truth));
    const TruthCheckSummary summary = Summarize(flags.terrains[i], runs.back().second);
    std::printf("%-8s %8d %12d %10.3f %12d %10d\n", summary.terrain.c_str(), summary.samples,
                summary.predicted_traversable, summary.Agreement(), summary.agree_traversable,
                summary.agree_untraversable);
    std::fflush(stdout);
    passed = passed && summary.Agreement() >= kRequiredAgreement;
  }
  if (flags.scenario.out) {
    OutputFolder folder(scenario.output_dir, "truth-check", flags.scenario.overwrite);
    TruthCheckOptions written = flags.check;
    written.terrain = scenario.terrain;
    WriteTruthCheck(runs, written, folder);
    folder.Commit();
    std::printf("written to %s (truth_check.csv, truth_check.json)\n", folder.final_path().c_str());
  }
  return passed ? kExitExpected : kExitOtherOutcome;
}

}  // namespace

Command AddTruthCheckCommand(CLI::App* app) {
  auto flags = std::make_shared<TruthCheckFlags>();
  CLI::App* command = app->add_subcommand(
      "truth-check",
      "Check the physical ground truth against the robot in MuJoCo: drive it 1 m from seeded "
      "poses (half predicted traversable) and compare; exit 1 if a terrain type agrees below 90 %");
  AddScenarioOptions(command, &flags->scenario);
  command->add_option("--terrains", flags->terrains, "Terrain types, comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  command->add_option("--samples", flags->check.samples, "Samples per terrain type")
      ->capture_default_str();
  return {command, [flags] { return TruthCheck(*flags); }};
}

}  // namespace trav::scenarios::cli
