// trav tune: controller and planner parameters tuned over scenarios and seeds (NLopt).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/input_error.h"
#include "scenarios/cli/cli.h"
#include "scenarios/experiments/tuning.h"

namespace trav::scenarios::cli {
namespace {

// Options of `trav tune`.
struct TuneCommand {
  std::string file;
  std::string out;
  std::optional<int> budget;
  std::optional<std::string> algorithm;
  int jobs{1};
  ClusterFlags cluster;
  std::vector<std::string> sets;
};

int Tune(const TuneCommand& command) {
  if (command.out.empty()) throw common::InputError("--out", "", "trav tune needs --out DIR");
  CheckJobs(command.jobs);
  TuneSpec spec = LoadTuneFile(command.file);
  spec.sets.insert(spec.sets.end(), command.sets.begin(), command.sets.end());
  if (command.budget) {
    if (*command.budget < 2 || *command.budget > 100000) {
      throw common::InputError("--budget", std::to_string(*command.budget),
                               "must be in [2, 100000]");
    }
    spec.budget = *command.budget;
  }
  if (command.algorithm) spec.algorithm = ParseTuneAlgorithm(*command.algorithm);
  TuneExecution execution;
  execution.jobs = command.jobs;
  execution.slurm = SlurmOf(command.cluster, "--runs-per-task");
  execution.trav_executable = SelfExecutable();
  const TuneResult result = RunTuning(spec, command.out, execution);
  if (result.interrupted) {
    std::printf("interrupted after %d evaluations; run the same command to resume\n",
                result.evaluations);
    return kExitOtherOutcome;
  }
  std::printf(
      "%d evaluations (%d from the folder): objective %.6g with the scenarios' values, "
      "%.6g tuned\n",
      result.evaluations, result.cached, result.initial_objective, result.best_objective);
  if (!spec.held_out_seeds.empty()) {
    std::printf("held-out seeds: %.6g with the scenarios' values, %.6g tuned\n",
                result.initial_held_out, result.best_held_out);
  }
  std::printf("report: %s/report.md, tuned values: %s/tuned.yaml\n", command.out.c_str(),
              command.out.c_str());
  return kExitExpected;
}

}  // namespace

Command AddTuneCommand(CLI::App* app) {
  auto command = std::make_shared<TuneCommand>();
  command->jobs = DefaultJobs();
  CLI::App* tune = app->add_subcommand(
      "tune",
      "Tune controller and planner parameters with a derivative-free optimiser (NLopt) over "
      "scenarios and seeds, and compare the result with the defaults on held-out seeds");
  tune->add_option("tuning", command->file, "Tuning YAML file (docs/tuning.md)")->required();
  tune->add_option("--out", command->out, "Output folder");
  tune->add_option("--budget", command->budget,
                   "Objective evaluations (overrides the file's budget)");
  tune->add_option("--algorithm", command->algorithm,
                   "bobyqa, neldermead, crs or esch (overrides the file's algorithm)");
  tune->add_option("--jobs", command->jobs, "Runs at once (local)")->capture_default_str();
  AddClusterFlags(tune, &command->cluster, "--runs-per-task");
  AddSetOption(tune, &command->sets, "every run's scenario, after the tuning file's `set`");
  return {tune, [command] { return Tune(*command); }};
}

}  // namespace trav::scenarios::cli
