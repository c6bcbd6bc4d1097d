// The trav command line: `trav run`, `trav scan`, `trav terrain`, `trav calibrate`, `trav eval`,
// `trav batch`, `trav tune`.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/input_error.h"
#include "common/logging.h"
#include "common/yaml_reader.h"
#include "scenarios/experiments/batch.h"
#include "scenarios/experiments/evaluation.h"
#include "scenarios/experiments/tuning.h"
#include "scenarios/run/calibration.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"
#include "scenarios/run/terrain_export.h"

namespace trav::scenarios {
namespace {

// Exit codes of DESIGN.md section 6.
constexpr int kExitExpected = 0;
constexpr int kExitOtherOutcome = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitInternalError = 3;

std::string ModelsDirectory() {
  const char* from_environment = std::getenv("TRAV_MODELS_DIR");
  return from_environment != nullptr ? from_environment : TRAV_MODELS_DIR;
}

// Options shared by the commands that read a scenario.
struct ScenarioOptions {
  std::string path;  // empty: the built-in default
  std::vector<std::string> sets;
  std::optional<std::uint64_t> seed;
  std::optional<std::string> out;
  bool overwrite{false};
};

void AddScenarioOptions(CLI::App* command, ScenarioOptions* options) {
  command->add_option("scenario", options->path,
                      "Scenario YAML file (default: the built-in hilly-terrain scenario)");
  command->add_option("--out", options->out, "Output folder (default: output.dir of the scenario)");
  command->add_flag("--overwrite", options->overwrite,
                    "Replace an earlier result of the same command in the output folder (trav "
                    "never replaces anything else)");
  command->add_option("--seed", options->seed, "Terrain seed (overrides terrain.seed)");
  command
      ->add_option("--set", options->sets,
                   "Override a scenario value: --set key.path=value (repeatable)")
      ->type_name("KEY=VALUE");
}

Scenario ResolveScenario(const ScenarioOptions& options, std::optional<bool> video) {
  common::YamlDocument document =
      options.path.empty()
          ? common::YamlDocument::Parse(DefaultScenarioYaml(), "<built-in default>")
          : common::YamlDocument::Load(options.path);
  ApplyOverrides(options.sets, &document);
  if (options.seed) document.Set("terrain.seed", std::to_string(*options.seed));
  if (video) document.Set("video.enabled", *video ? "true" : "false");
  if (options.out) document.SetString("output.dir", *options.out);
  return LoadScenario(document);
}

// The robot model file of a scenario, checked before anything is written.
// @throws common::InputError if it is not a robot model trav can drive.
std::string ExistingRobotModel(const Scenario& scenario) {
  return CheckedRobotModelPath(scenario, ModelsDirectory());
}

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

// Runs a resolved scenario into its output folder; prints and returns the summary.
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

// Fakes the failure a scenario asks for (test_fault): a crash, or a run that never ends. A test
// hook, so only where the environment enables it (TRAV_TEST_FAULTS=1, docs/reliability.md).
void InjectFault(TestFault fault) {
  if (fault == TestFault::kNone) return;
  const char* enabled = std::getenv("TRAV_TEST_FAULTS");
  if (enabled == nullptr || std::string(enabled) != "1") {
    throw common::InputError("test_fault", "",
                             "is a test hook; it works only with TRAV_TEST_FAULTS=1 in the "
                             "environment");
  }
  if (fault == TestFault::kCrash) std::abort();
  while (fault == TestFault::kHang) pause();
}

int Run(const ScenarioOptions& options, std::optional<bool> video, bool record_clouds) {
  const Scenario scenario = ResolveScenario(options, video);
  InjectFault(scenario.test_fault);
  RunOptions run_options;
  run_options.record_clouds = record_clouds;
  const RunSummary summary = RunInFolder(scenario, run_options, options.overwrite);
  const std::string& out = scenario.output_dir;

  std::printf("outcome: %s (expected %s)\n", OutcomeName(summary.outcome),
              OutcomeName(scenario.expected_outcome));
  std::printf("simulated %.1f s in %.1f s wall time (%.1fx real time), drove %.1f m\n",
              summary.sim_time_s, summary.wall_time_s, summary.real_time_factor,
              summary.distance_m);
  if (summary.lidar_frames > 0) {
    std::printf("lidar: %d frames, %.0f points and %.2f ms of ray casting per frame%s\n",
                summary.lidar_frames, summary.lidar_points_per_frame, summary.lidar_ms_per_frame,
                record_clouds ? " (clouds/*.pcd)" : "");
  }
  std::printf("summary: %s/summary.json\n", out.c_str());
  if (summary.video_frames > 0) {
    std::printf("video:   %s/video.mp4 (%d frames)\n", out.c_str(), summary.video_frames);
  }
  return summary.outcome == scenario.expected_outcome ? kExitExpected : kExitOtherOutcome;
}

int Scan(const ScenarioOptions& options, int frames) {
  if (!options.out) throw common::InputError("--out", "", "trav scan needs --out DIR");
  if (frames < 1) throw common::InputError("--frames", std::to_string(frames), "must be >= 1");
  Scenario scenario = ResolveScenario(options, false);
  if (!scenario.lidar.enabled)
    throw common::InputError("lidar.enabled", "false", "trav scan needs the LiDAR");
  // run long enough for the frames, whatever the scenario's duration
  scenario.duration_s = std::max(scenario.duration_s, (frames + 1) * scenario.lidar.frame_period_s);
  RunOptions run_options;
  run_options.record_clouds = true;
  run_options.max_lidar_frames = frames;
  const RunSummary summary = RunInFolder(scenario, run_options, options.overwrite);
  std::printf(
      "%d frames of %.0f points on average written to %s/clouds (PCD: x y z in the sensor frame, "
      "time, line)\n",
      summary.lidar_frames, summary.lidar_points_per_frame, scenario.output_dir.c_str());
  return summary.outcome == Outcome::kCompleted ? kExitExpected : kExitOtherOutcome;
}

int Terrain(const ScenarioOptions& options) {
  ScenarioOptions terrain_options = options;
  if (!terrain_options.out) throw common::InputError("--out", "", "trav terrain needs --out DIR");
  const Scenario scenario = ResolveScenario(terrain_options, std::nullopt);
  OutputFolder folder(scenario.output_dir, "terrain", options.overwrite);
  const TerrainExportSummary written = ExportScenarioTerrain(scenario, folder);
  folder.Commit();
  std::printf("terrain %s (seed %llu): %d x %d samples, %zu obstacles\n",
              written.terrain_type.c_str(), static_cast<unsigned long long>(scenario.terrain.seed),
              written.num_x, written.num_y, written.obstacles);
  std::printf(
      "written to %s (heightmap.png, heightmap.raw, cloud.pcd, preview.png, ground_truth.png, "
      "ground_truth.raw, terrain.json)\n",
      folder.final_path().c_str());
  return kExitExpected;
}

int Calibrate(const ScenarioOptions& options) {
  const Scenario scenario = ResolveScenario(options, std::nullopt);
  const std::string model = ExistingRobotModel(scenario);
  const CalibrationResult result = CalibrateSkidSteer(model, scenario.skid_steer);
  std::printf("skid-steer calibration of %s on flat ground (effective_track_factor %.3f)\n",
              model.c_str(), scenario.skid_steer.effective_track_factor);
  std::printf("%12s %14s %12s %14s\n", "cmd v [m/s]", "cmd w [rad/s]", "v [m/s]", "w [rad/s]");
  for (const CalibrationSample& sample : result.samples) {
    std::printf("%12.2f %14.2f %12.3f %14.3f\n", sample.commanded_v_m_s,
                sample.commanded_omega_rad_s, sample.measured_v_m_s, sample.measured_omega_rad_s);
  }
  std::printf("effective_track_factor that matches the commanded yaw rates: %.3f\n",
              result.effective_track_factor);
  return kExitExpected;
}

// The command line as typed, for the report.
std::string CommandLine(int argc, char** argv) {
  std::string line = "trav";
  for (int i = 1; i < argc; ++i) line += std::string(" ") + argv[i];
  return line;
}

// Where a batch or evaluation runs: local processes, or a Slurm job array.
struct ClusterFlags {
  bool slurm{false};
  bool no_wait{false};
  SlurmOptions options;
};

void AddClusterFlags(CLI::App* command, ClusterFlags* flags, const std::string& per_task_flag) {
  command->add_flag("--slurm", flags->slurm, "Submit a Slurm job array instead of local processes");
  command->add_option("--partition", flags->options.partition, "Slurm partition");
  command->add_option("--time", flags->options.time, "Slurm time limit per array task (HH:MM:SS)");
  command->add_option(per_task_flag, flags->options.jobs_per_task, "Jobs per Slurm array task")
      ->capture_default_str();
  command->add_flag("--no-wait", flags->no_wait,
                    "With --slurm: return once submitted (then --collect DIR)");
}

// The Slurm options of the flags, or nothing for local processes.
std::optional<SlurmOptions> SlurmOf(const ClusterFlags& flags, const std::string& per_task_flag) {
  if (!flags.slurm) return std::nullopt;
  if (flags.options.jobs_per_task < 1 || flags.options.jobs_per_task > 100000) {
    throw common::InputError(per_task_flag, std::to_string(flags.options.jobs_per_task),
                             "must be in [1, 100000]");
  }
  ValidateSlurmOptions(flags.options);
  SlurmOptions options = flags.options;
  options.wait = !flags.no_wait;
  options.trav_executable = std::filesystem::read_symlink("/proc/self/exe").string();
  return options;
}

int Eval(const EvalOptions& options, const std::string& out, const std::string& command_line,
         const ClusterFlags& cluster, const std::string& collect) {
  if (!collect.empty()) {
    const int finished = CollectEvaluation(collect);
    std::printf("%d scenes finished; results: %s/results.md\n", finished, collect.c_str());
    return kExitExpected;
  }
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  const EvalRunResult result =
      RunEvaluation(options, out, self, command_line, isatty(STDERR_FILENO) != 0,
                    SlurmOf(cluster, "--scenes-per-task"));
  if (!result.slurm_job.empty() && cluster.no_wait) {
    std::printf("Slurm job %s submitted; when it has ended: trav eval --collect %s\n",
                result.slurm_job.c_str(), out.c_str());
    return kExitExpected;
  }
  if (result.interrupted) {
    std::printf("interrupted: %d of %d scenes finished in %s; run the same command to resume\n",
                result.resumed + result.finished, result.scenes, out.c_str());
    return kExitOtherOutcome;
  }
  std::printf("%d scenes finished (%d kept from before), %d failed\n",
              result.resumed + result.finished, result.resumed, result.failed);
  std::printf("results: %s/results.md (results.json, results.csv, plots)\n", out.c_str());
  return result.failed == 0 ? kExitExpected : kExitOtherOutcome;
}

// Options of `trav batch`.
struct BatchCommand {
  std::string file;
  std::string out;
  std::string collect;
  int jobs{1};
  ClusterFlags cluster;
};

int Batch(const BatchCommand& command) {
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  if (!command.collect.empty()) {
    const CampaignFolder folder(command.collect, "batch", "batch.json", kBatchPartialSubfolders,
                                CampaignFolder::Use::kExisting);
    const int finished = CollectBatch(command.collect);
    std::printf("%d runs with results; report: %s/report.md\n", finished, command.collect.c_str());
    return kExitExpected;
  }
  if (command.file.empty()) throw common::InputError("BATCH.yaml", "", "trav batch needs a file");
  if (command.out.empty()) throw common::InputError("--out", "", "trav batch needs --out DIR");
  if (command.jobs < 1 || command.jobs > 1024) {
    throw common::InputError("--jobs", std::to_string(command.jobs), "must be in [1, 1024]");
  }
  const BatchSpec spec = LoadBatchFile(command.file);
  const std::vector<BatchRun> runs = ExpandBatch(spec);
  const std::optional<SlurmOptions> slurm = SlurmOf(command.cluster, "--runs-per-task");
  const CampaignFolder folder(command.out, "batch", "batch.json", kBatchPartialSubfolders);
  const std::vector<BatchRun> pending = PrepareBatchFolder(spec, runs, command.out);
  if (slurm) {
    const std::string job = SubmitBatchToSlurm(spec, pending, command.out, *slurm);
    if (!slurm->wait && !job.empty()) {
      std::printf("job %s submitted; gather what has finished with: trav batch --collect %s\n",
                  job.c_str(), command.out.c_str());
    } else {
      std::printf("report: %s/report.md\n", command.out.c_str());
    }
    return kExitExpected;
  }
  LocalBatchOptions options;
  options.jobs = command.jobs;
  options.trav_executable = self;
  options.progress_bar = isatty(STDERR_FILENO) != 0;
  const BatchProgress progress = RunBatchLocally(spec, runs, pending, command.out, options);
  if (progress.interrupted) {
    std::printf("interrupted: %d of %d runs finished in %s; run the same command to resume\n",
                progress.resumed + progress.finished, progress.runs, command.out.c_str());
    return kExitOtherOutcome;
  }
  std::printf("%d runs finished (%d kept from before), %d failed; report: %s/report.md\n",
              progress.resumed + progress.finished, progress.resumed, progress.failed,
              command.out.c_str());
  return progress.failed == 0 ? kExitExpected : kExitOtherOutcome;
}

// Options of `trav tune`.
struct TuneCommand {
  std::string file;
  std::string out;
  std::optional<int> budget;
  std::optional<std::string> algorithm;
  int jobs{1};
  ClusterFlags cluster;
};

int Tune(const TuneCommand& command) {
  if (command.out.empty()) throw common::InputError("--out", "", "trav tune needs --out DIR");
  if (command.jobs < 1 || command.jobs > 1024) {
    throw common::InputError("--jobs", std::to_string(command.jobs), "must be in [1, 1024]");
  }
  TuneSpec spec = LoadTuneFile(command.file);
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
  execution.trav_executable = std::filesystem::read_symlink("/proc/self/exe").string();
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

int Main(int argc, char** argv) {
  CLI::App app{"trav: physics-simulated navigation testbed for the Scout Mini on uneven terrain"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Help for every command");
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose,
               "Log debug messages (MuJoCo warnings as they happen) to stderr");

  ScenarioOptions run_options;
  std::optional<bool> video;
  CLI::App* run = app.add_subcommand("run",
                                     "Run a scenario and write summary.json, trajectory.csv "
                                     "and video.mp4 into its output folder");
  AddScenarioOptions(run, &run_options);
  run->add_flag_callback(
      "--video", [&] { video = true; }, "Record video.mp4 (overrides video.enabled)");
  run->add_flag_callback(
      "--no-video", [&] { video = false; }, "Do not record a video");
  bool record_clouds = false;
  run->add_flag("--record-clouds", record_clouds,
                "Write every LiDAR frame as clouds/frame_NNNNNN.pcd");

  ScenarioOptions scan_options;
  int scan_frames = 10;
  CLI::App* scan = app.add_subcommand(
      "scan", "Drive the scenario's robot and write N LiDAR frames as PCD (no video)");
  AddScenarioOptions(scan, &scan_options);
  scan->add_option("--frames", scan_frames, "Number of frames to write")->capture_default_str();

  ScenarioOptions terrain_options;
  CLI::App* terrain = app.add_subcommand(
      "terrain", "Generate a scenario's terrain and export heightmap, point cloud and preview");
  AddScenarioOptions(terrain, &terrain_options);

  ScenarioOptions calibrate_options;
  CLI::App* calibrate = app.add_subcommand(
      "calibrate", "Measure the skid-steer mapping of the scenario's robot on flat ground");
  AddScenarioOptions(calibrate, &calibrate_options);

  EvalOptions eval_options;
  eval_options.jobs = std::max(1u, std::thread::hardware_concurrency());
  std::string eval_out = "out/eval";
  bool no_ablation = false;
  CLI::App* eval = app.add_subcommand(
      "eval",
      "Evaluate the mappers against the ground truth over seeded scenes of each terrain type "
      "(the paper's Tables I-III, error over time, inducing-point ablation); resumable");
  eval->add_option("--out", eval_out, "Output folder")->capture_default_str();
  eval->add_option("--scenes", eval_options.scenes, "Scenes per terrain type")
      ->capture_default_str();
  eval->add_option("--seed", eval_options.seed, "Terrain seed of each type's first scene")
      ->capture_default_str();
  eval->add_option("--jobs", eval_options.jobs, "Scenes run at once (worker processes)")
      ->capture_default_str();
  eval->add_option("--terrains", eval_options.terrains, "Terrain types, comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  eval->add_option("--methods", eval_options.methods,
                   "Methods, comma-separated: sgp, fsgp, fsgp-bgk, fsgp-accumulation, em, "
                   "ground-truth, constant=C")
      ->delimiter(',')
      ->capture_default_str();
  eval->add_option("--inducing", eval_options.inducing_points,
                   "FSGP-BGK inducing-point counts of the ablation, comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  eval->add_flag("--no-ablation", no_ablation, "Skip the inducing-point ablation");
  eval->add_option("--route-length", eval_options.route_length_m, "Distance from start to goal [m]")
      ->capture_default_str();
  eval->add_option("--frames", eval_options.max_frames,
                   "LiDAR frames per scene (0: until the drive ends)")
      ->capture_default_str();
  eval->add_option("--time-limit", eval_options.scene_time_limit_s,
                   "Wall time allowed per scene [s]")
      ->capture_default_str();
  ClusterFlags eval_cluster;
  std::string eval_collect;
  AddClusterFlags(eval, &eval_cluster, "--scenes-per-task");
  eval->add_option("--collect", eval_collect,
                   "Write the report of the evaluation in DIR from what has finished");
  eval->add_option("--set", eval_options.sets,
                   "Override a value of every scene's scenario: --set key.path=value")
      ->type_name("KEY=VALUE");

  BatchCommand batch_command;
  batch_command.jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  CLI::App* batch = app.add_subcommand(
      "batch",
      "Run many scenarios from a batch file (a sweep or a list) as local processes or a Slurm job "
      "array, and gather every result into one report; resumable");
  batch->add_option("batch", batch_command.file, "Batch YAML file (docs/batch.md)");
  batch->add_option("--out", batch_command.out, "Output folder");
  batch->add_option("--jobs", batch_command.jobs, "Runs at once (local)")->capture_default_str();
  AddClusterFlags(batch, &batch_command.cluster, "--runs-per-task");
  batch->add_option("--collect", batch_command.collect,
                    "Write the report of the batch in DIR from what has finished");

  TuneCommand tune_command;
  tune_command.jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  CLI::App* tune = app.add_subcommand(
      "tune",
      "Tune controller and planner parameters with a derivative-free optimiser (NLopt) over "
      "scenarios and seeds, and compare the result with the defaults on held-out seeds");
  tune->add_option("tuning", tune_command.file, "Tuning YAML file (docs/tuning.md)")->required();
  tune->add_option("--out", tune_command.out, "Output folder");
  tune->add_option("--budget", tune_command.budget,
                   "Objective evaluations (overrides the file's budget)");
  tune->add_option("--algorithm", tune_command.algorithm,
                   "bobyqa, neldermead, crs or esch (overrides the file's algorithm)");
  tune->add_option("--jobs", tune_command.jobs, "Runs at once (local)")->capture_default_str();
  AddClusterFlags(tune, &tune_command.cluster, "--runs-per-task");

  std::string task_file;
  int task_index = 0;
  CLI::App* job_task = app.add_subcommand("job-task", "");  // a Slurm array task (hidden)
  job_task->group("");
  job_task->add_option("tasks", task_file)->required();
  job_task->add_option("index", task_index)->required();

  std::string scene_folder, scene_terrain;
  std::uint64_t scene_seed = 0;
  CLI::App* eval_scene = app.add_subcommand("eval-scene", "");  // trav eval's worker (hidden)
  eval_scene->group("");
  eval_scene->add_option("folder", scene_folder)->required();
  eval_scene->add_option("terrain", scene_terrain)->required();
  eval_scene->add_option("seed", scene_seed)->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitExpected : kExitBadInput;
  }

  if (verbose) common::SetLogLevel(common::LogLevel::kDebug);
  try {
    if (run->parsed()) return Run(run_options, video, record_clouds);
    if (scan->parsed()) return Scan(scan_options, scan_frames);
    if (calibrate->parsed()) return Calibrate(calibrate_options);
    if (eval->parsed()) {
      if (no_ablation) eval_options.inducing_points.clear();
      return Eval(eval_options, eval_out, CommandLine(argc, argv), eval_cluster, eval_collect);
    }
    if (batch->parsed()) return Batch(batch_command);
    if (tune->parsed()) return Tune(tune_command);
    if (job_task->parsed()) {
      RunJobTask(task_file, task_index);
      return kExitExpected;
    }
    if (eval_scene->parsed()) {
      RunEvalSceneInFolder(scene_folder, {scene_terrain, scene_seed}, ModelsDirectory());
      return kExitExpected;
    }
    return Terrain(terrain_options);
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

}  // namespace
}  // namespace trav::scenarios

int main(int argc, char** argv) { return trav::scenarios::Main(argc, argv); }
