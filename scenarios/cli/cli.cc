#include "scenarios/cli/cli.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "common/input_error.h"
#include "common/yaml_reader.h"
#include "scenarios/run/output_folder.h"

namespace trav::scenarios::cli {
namespace {

// A progress bar on a terminal; nothing when stderr is a file or pipe.
ProgressCallback TerminalProgress() {
  if (!isatty(STDERR_FILENO)) return {};
  return [](double fraction) {
    const int width = 40;
    const int filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "\r[%s%s] %3d%%", std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), static_cast<int>(fraction * 100));
    if (fraction >= 1.0) std::fprintf(stderr, "\n");
  };
}

}  // namespace

std::string ModelsDirectory() {
  const char* from_environment = std::getenv("TRAV_MODELS_DIR");
  if (from_environment != nullptr) return from_environment;
  // the build's source tree; else, installed (cmake --install), <prefix>/share/trav/models beside
  // <prefix>/bin/trav
  std::error_code error;
  if (std::filesystem::is_directory(TRAV_MODELS_DIR, error)) return TRAV_MODELS_DIR;
  const std::filesystem::path installed =
      std::filesystem::path(SelfExecutable()).parent_path().parent_path() / "share/trav/models";
  return std::filesystem::is_directory(installed, error) ? installed.string() : TRAV_MODELS_DIR;
}

std::string SelfExecutable() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

const CLI::Validator& SeedValidator() {
  static const CLI::Validator kSeed(
      [](const std::string& text) {
        const bool digits = !text.empty() && text.size() <= 20 &&
                            text.find_first_not_of("0123456789") == std::string::npos;
        return digits ? std::string() : "expected a seed (a non-negative integer), got " + text;
      },
      "SEED");
  return kSeed;
}

void AddSetOption(CLI::App* command, std::vector<std::string>* sets, const std::string& what) {
  command
      ->add_option("--set", *sets,
                   "Override a value of " + what +
                       ": --set key.path=value "
                       "(repeatable; YAML values)")
      ->type_name("KEY=VALUE");
}

void AddScenarioOptions(CLI::App* command, ScenarioOptions* options) {
  command->add_option(
      "scenario", options->path,
      "Scenario YAML file (default: the built-in scenario, a 30 m drive through a forest)");
  command->add_option("--out", options->out, "Output folder (default: output.dir of the scenario)");
  command->add_flag("--overwrite", options->overwrite,
                    "Replace an earlier result of the same command in the output folder (trav "
                    "never replaces anything else)");
  command->add_option("--seed", options->seed, "Terrain seed (overrides terrain.seed)")
      ->check(SeedValidator());
  AddSetOption(command, &options->sets, "the scenario");
}

Scenario ResolveScenario(const ScenarioOptions& options, std::optional<bool> video,
                         std::optional<bool> mcap) {
  common::YamlDocument document =
      options.path.empty()
          ? common::YamlDocument::Parse(DefaultScenarioYaml(), "<built-in default>")
          : common::YamlDocument::Load(options.path);
  ApplyOverrides(options.sets, &document);
  if (options.seed) document.Set("terrain.seed", std::to_string(*options.seed));
  if (video) document.Set("video.enabled", *video ? "true" : "false");
  if (mcap) document.Set("output.mcap", *mcap ? "true" : "false");
  if (options.out) document.SetString("output.dir", *options.out);
  return LoadScenario(document);
}

std::string ExistingRobotModel(const Scenario& scenario) {
  return CheckedRobotModelPath(scenario, ModelsDirectory());
}

RunSummary RunInFolder(const Scenario& scenario, const RunOptions& run_options, bool overwrite) {
  const std::string model = ExistingRobotModel(scenario);
  OutputFolder folder(scenario.output_dir, "run", overwrite);
  WriteTextFile(folder.File("scenario.yaml"), ResolvedScenarioYaml(scenario));
  const RunSummary summary =
      RunScenario(scenario, model, folder.File(""), run_options, TerminalProgress());
  WriteTextFile(folder.File("summary.json"), SummaryJson(scenario, summary));
  folder.Commit();
  return summary;
}

void AddClusterFlags(CLI::App* command, ClusterFlags* flags, const std::string& per_task_flag) {
  command->add_flag("--slurm", flags->slurm, "Submit a Slurm job array instead of local processes");
  command->add_option("--partition", flags->options.partition, "Slurm partition");
  command->add_option("--time", flags->options.time, "Slurm time limit per array task (HH:MM:SS)");
  command->add_option(per_task_flag, flags->options.jobs_per_task, "Jobs per Slurm array task")
      ->capture_default_str();
  command->add_flag("--no-wait", flags->no_wait,
                    "With --slurm: return once submitted (then --collect DIR)");
}

std::optional<SlurmOptions> SlurmOf(const ClusterFlags& flags, const std::string& per_task_flag) {
  if (!flags.slurm) return std::nullopt;
  if (flags.options.jobs_per_task < 1 || flags.options.jobs_per_task > 100000) {
    throw common::InputError(per_task_flag, std::to_string(flags.options.jobs_per_task),
                             "must be in [1, 100000]");
  }
  ValidateSlurmOptions(flags.options);
  SlurmOptions options = flags.options;
  options.wait = !flags.no_wait;
  options.trav_executable = SelfExecutable();
  return options;
}

void CheckJobs(int jobs) {
  if (jobs < 1 || jobs > 1024) {
    throw common::InputError("--jobs", std::to_string(jobs), "must be in [1, 1024]");
  }
}

int DefaultJobs() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

}  // namespace trav::scenarios::cli
