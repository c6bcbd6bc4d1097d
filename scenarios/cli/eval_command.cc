// trav eval: the mappers against the ground truth over seeded scenes (the paper's tables).
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>

#include "scenarios/cli/cli.h"
#include "scenarios/experiments/evaluation.h"

namespace trav::scenarios::cli {
namespace {

struct EvalFlags {
  EvalOptions options;
  std::string out{"out/eval"};
  bool no_ablation{false};
  ClusterFlags cluster;
  std::string collect;
};

int Eval(const EvalOptions& options, const std::string& out, const std::string& command_line,
         const ClusterFlags& cluster, const std::string& collect) {
  if (!collect.empty()) {
    const int finished = CollectEvaluation(collect);
    std::printf("%d scenes finished; results: %s/results.md\n", finished, collect.c_str());
    return kExitExpected;
  }
  const std::string self = SelfExecutable();
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

// Registers the evaluation's options (its scenes, methods and ablation).
void AddEvalOptions(CLI::App* eval, EvalFlags* flags) {
  EvalOptions& options = flags->options;
  eval->add_option("--out", flags->out, "Output folder")->capture_default_str();
  eval->add_option("--scenes", options.scenes, "Scenes per terrain type")->capture_default_str();
  eval->add_option("--seed", options.seed, "Terrain seed of each type's first scene")
      ->check(SeedValidator())
      ->capture_default_str();
  eval->add_option("--jobs", options.jobs, "Scenes run at once (worker processes)")
      ->capture_default_str();
  eval->add_option("--terrains", options.terrains, "Terrain types, comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  eval->add_option("--methods", options.methods,
                   "Methods, comma-separated: sgp, fsgp, fsgp-bgk, fsgp-accumulation, em, "
                   "ground-truth, constant=C")
      ->delimiter(',')
      ->capture_default_str();
  eval->add_option("--inducing", options.inducing_points,
                   "Inducing-point counts of the ablation of SGP, FSGP and FSGP-BGK (those among "
                   "--methods), comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  eval->add_flag("--no-ablation", flags->no_ablation, "Skip the inducing-point ablation");
  eval->add_option(
          "--pose-sources", options.pose_sources,
          "Pose sources of the mappers besides the true pose (drift-model, scan-matching), "
          "comma-separated: each runs every mapper of --methods as <method>@<source>")
      ->delimiter(',');
  eval->add_option("--truth", options.truth,
                   "Ground truth the maps are scored against: physical (the robot resting on the "
                   "world against its measured limits) or geometric (the mappers' score formula on "
                   "exact heights)")
      ->capture_default_str();
  eval->add_option("--route-length", options.route_length_m, "Distance from start to goal [m]")
      ->capture_default_str();
  eval->add_option("--frames", options.max_frames,
                   "LiDAR frames per scene (0: until the drive ends)")
      ->capture_default_str();
  eval->add_option("--time-limit", options.scene_time_limit_s, "Wall time allowed per scene [s]")
      ->capture_default_str();
}

}  // namespace

Command AddEvalCommand(CLI::App* app, const std::string& command_line) {
  auto flags = std::make_shared<EvalFlags>();
  flags->options.jobs = DefaultJobs();
  CLI::App* eval = app->add_subcommand(
      "eval",
      "Evaluate the mappers against the ground truth over seeded scenes of each terrain type "
      "(the paper's Tables I-III, error over time, inducing-point ablation); resumable");
  AddEvalOptions(eval, flags.get());
  AddClusterFlags(eval, &flags->cluster, "--scenes-per-task");
  eval->add_option("--collect", flags->collect,
                   "Write the report of the evaluation in DIR from what has finished");
  AddSetOption(eval, &flags->options.sets, "every scene's scenario");
  return {eval, [flags, command_line] {
            if (flags->no_ablation) flags->options.inducing_points.clear();
            return Eval(flags->options, flags->out, command_line, flags->cluster, flags->collect);
          }};
}

}  // namespace trav::scenarios::cli
