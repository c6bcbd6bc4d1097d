// trav batch: many scenarios from a batch file, locally or as a Slurm job array, one report.
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/input_error.h"
#include "scenarios/cli/cli.h"
#include "scenarios/experiments/batch.h"
#include "scenarios/run/output_folder.h"

namespace trav::scenarios::cli {
namespace {

// Options of `trav batch`.
struct BatchCommand {
  std::string file;
  std::string out;
  std::string collect;
  int jobs{1};
  ClusterFlags cluster;
  std::vector<std::string> sets;
};

int Batch(const BatchCommand& command) {
  const std::string self = SelfExecutable();
  if (!command.collect.empty()) {
    const CampaignFolder folder(command.collect, "batch", "batch.json", kBatchPartialSubfolders,
                                CampaignFolder::Use::kExisting);
    const int finished = CollectBatch(command.collect);
    std::printf("%d runs with results; report: %s/report.md\n", finished, command.collect.c_str());
    return kExitExpected;
  }
  if (command.file.empty()) throw common::InputError("BATCH.yaml", "", "trav batch needs a file");
  if (command.out.empty()) throw common::InputError("--out", "", "trav batch needs --out DIR");
  CheckJobs(command.jobs);
  BatchSpec spec = LoadBatchFile(command.file);
  spec.sets.insert(spec.sets.end(), command.sets.begin(), command.sets.end());
  const std::vector<BatchRun> runs = ExpandBatch(spec);
  const std::optional<SlurmOptions> slurm = SlurmOf(command.cluster, "--runs-per-task");
  const CampaignFolder folder(command.out, "batch", "batch.json", kBatchPartialSubfolders);
  const std::vector<BatchRun> pending = PrepareBatchFolder(spec, runs, folder);
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

}  // namespace

Command AddBatchCommand(CLI::App* app) {
  auto command = std::make_shared<BatchCommand>();
  command->jobs = DefaultJobs();
  CLI::App* batch = app->add_subcommand(
      "batch",
      "Run many scenarios from a batch file (a sweep or a list) as local processes or a Slurm job "
      "array, and gather every result into one report; resumable");
  batch->add_option("batch", command->file, "Batch YAML file (docs/batch.md)");
  batch->add_option("--out", command->out, "Output folder");
  batch->add_option("--jobs", command->jobs, "Runs at once (local)")->capture_default_str();
  AddClusterFlags(batch, &command->cluster, "--runs-per-task");
  batch->add_option("--collect", command->collect,
                    "Write the report of the batch in DIR from what has finished");
  AddSetOption(batch, &command->sets, "every run's scenario, after the batch file's `set`");
  return {batch, [command] { return Batch(*command); }};
}

}  // namespace trav::scenarios::cli
