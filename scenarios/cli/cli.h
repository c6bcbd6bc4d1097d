#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "scenarios/experiments/job_array.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios::cli {

/// Exit codes (docs/architecture.md): the expected outcome, another outcome, bad input, an
/// internal error.
constexpr int kExitExpected = 0;
constexpr int kExitOtherOutcome = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitInternalError = 3;

/// A subcommand registered with CLI11: its parser, and what runs it once parsed (returning the
/// exit code; it may throw common::InputError and the other errors Main maps to exit codes).
struct Command {
  CLI::App* parser;
  std::function<int()> run;
};

/// The subcommands, each in its own file, in the order `trav --help` lists them.
Command AddRunCommand(CLI::App* app);
Command AddScanCommand(CLI::App* app);
Command AddTerrainCommand(CLI::App* app);
Command AddPatternCommand(CLI::App* app);
Command AddCalibrateCommand(CLI::App* app);
Command AddTruthCheckCommand(CLI::App* app);
Command AddUrdfCommand(CLI::App* app);
/// `command_line`: the command as typed, for the evaluation's report.
Command AddEvalCommand(CLI::App* app, const std::string& command_line);
Command AddBatchCommand(CLI::App* app);
Command AddTuneCommand(CLI::App* app);
/// The hidden workers: a Slurm array task, and one scene of `trav eval`.
Command AddJobTaskCommand(CLI::App* app);
Command AddEvalSceneCommand(CLI::App* app);

/// The folder of robot models: TRAV_MODELS_DIR from the environment, else the build's.
std::string ModelsDirectory();

/// The running trav executable (for the processes it starts).
std::string SelfExecutable();

/// Options shared by the commands that read a scenario.
struct ScenarioOptions {
  std::string path;  ///< empty: the built-in default
  std::vector<std::string> sets;
  std::optional<std::uint64_t> seed;
  std::optional<std::string> out;
  bool overwrite{false};
};

/// Registers the scenario positional, --out, --overwrite, --seed and --set.
void AddScenarioOptions(CLI::App* command, ScenarioOptions* options);

/// Adds `--set KEY=VALUE` (repeatable) to `command`: scenario overrides, `what` says which
/// scenarios they apply to.
void AddSetOption(CLI::App* command, std::vector<std::string>* sets, const std::string& what);

/// Accepts a seed: digits only (CLI11 would read "-1" into an unsigned as 2^64 - 1).
const CLI::Validator& SeedValidator();

/// The scenario of the options: the file (or the built-in default) with --set, --seed, --out and
/// the video and MCAP choices applied. @throws common::InputError on bad input.
Scenario ResolveScenario(const ScenarioOptions& options, std::optional<bool> video,
                         std::optional<bool> mcap = std::nullopt);

/// The robot model file of a scenario, checked before anything is written.
/// @throws common::InputError if it is not a robot model trav can drive.
std::string ExistingRobotModel(const Scenario& scenario);

/// Runs a resolved scenario into its output folder (scenario.yaml, the run's files and
/// summary.json, committed at the end) with a progress bar on a terminal; returns the summary.
RunSummary RunInFolder(const Scenario& scenario, const RunOptions& run_options, bool overwrite);

/// Where a batch, tuning or evaluation runs: local processes, or a Slurm job array.
struct ClusterFlags {
  bool slurm{false};
  bool no_wait{false};
  SlurmOptions options;
};

/// Registers --slurm, --partition, --time, `per_task_flag` and --no-wait.
void AddClusterFlags(CLI::App* command, ClusterFlags* flags, const std::string& per_task_flag);

/// The Slurm options of the flags, or nothing for local processes.
/// @throws common::InputError for invalid values.
std::optional<SlurmOptions> SlurmOf(const ClusterFlags& flags, const std::string& per_task_flag);

/// Checks a --jobs value. @throws common::InputError if it is not in [1, 1024].
void CheckJobs(int jobs);

/// The default of --jobs: the machine's cores.
int DefaultJobs();

}  // namespace trav::scenarios::cli
