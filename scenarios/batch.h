#pragma once

#include <string>
#include <utility>
#include <vector>

#include "scenarios/process_pool.h"

namespace trav::scenarios {

/// One axis of a batch's sweep: a scenario key and the values it takes.
struct SweepAxis {
  std::string label;                ///< its name in run ids and reports ("seed", "mapper", ...)
  std::string key_path;             ///< the scenario key it sets ("terrain.seed")
  std::vector<std::string> values;  ///< the YAML text of each value
};

/// A batch file (docs/batch.md): base scenarios, a sweep, fixed overrides and limits.
struct BatchSpec {
  std::string source;                  ///< the batch file
  std::string name;                    ///< `name`, default the file's stem
  std::vector<std::string> scenarios;  ///< base scenario files (paths as resolved)
  std::vector<SweepAxis> axes;         ///< every run takes one value of each axis
  std::vector<std::string> sets;       ///< `set`: key.path=value applied to every run
  double time_limit_s{1800.0};         ///< wall time allowed per run [s]
};

/// One run of a batch: a base scenario with one value of each sweep axis.
struct BatchRun {
  /// Stable id: the scenario's name, then label-value for each axis ("suite_hilly_seed-3"); the
  /// name of its result folder.
  std::string id;
  std::string scenario_name;
  std::vector<std::pair<std::string, std::string>> parameters;  ///< (label, value) per axis
  std::string scenario_yaml;                                    ///< the fully resolved scenario
};

/// Reads a batch file strictly. @throws common::InputError naming the file, key and value
/// (unknown key, empty sweep, no scenario).
BatchSpec LoadBatchFile(const std::string& path);

/// Expands a batch into its runs (every base scenario crossed with every combination of the
/// axes' values, in file order). @throws common::InputError naming the batch file if a run's
/// scenario does not load (a swept or set key that does not exist, a bad value) or two runs get
/// the same id.
std::vector<BatchRun> ExpandBatch(const BatchSpec& spec);

/// How each run of a batch ended.
struct BatchProgress {
  int runs{0};      ///< in the batch
  int resumed{0};   ///< finished before and kept
  int finished{0};  ///< finished now (whatever their outcome)
  int failed{0};    ///< crashed, killed, timed out or failed to run (recorded under failed/)
  bool interrupted{false};
};

/// Settings of a local batch.
struct LocalBatchOptions {
  int jobs{1};                  ///< runs at once, >= 1
  std::string trav_executable;  ///< the `trav` that runs each scenario
  bool progress_bar{false};     ///< redraw one line on stderr, else one line per run
};

/// Settings of a Slurm submission.
struct SlurmOptions {
  std::string partition;        ///< empty: the cluster's default
  std::string time;             ///< per array task ("HH:MM:SS"), empty: the partition's default
  int runs_per_task{1};         ///< runs per array task, >= 1
  bool wait{true};              ///< wait for the job, then write the report
  std::string trav_executable;  ///< the `trav` the tasks run (on a shared filesystem)
};

/// Lays out `out_dir` for the runs: batch.json (the runs and the limits), scenarios/<id>.yaml,
/// runs/, logs/, failed/; removes what a killed run left half-written. Returns the runs not yet
/// finished (no runs/<id>/summary.json). @throws common::InputError if `out_dir` holds another
/// batch (other runs or scenarios).
std::vector<BatchRun> PrepareBatchFolder(const BatchSpec& spec, const std::vector<BatchRun>& runs,
                                         const std::string& out_dir);

/// Runs the pending runs as local `trav run` processes (a crash, a hang past the time limit or a
/// kill of one is recorded as that run's outcome under failed/<id>.json, and the others go on),
/// then writes the report (WriteBatchReport) unless interrupted (SIGINT, SIGTERM: running runs
/// are stopped and lost, finished ones kept).
BatchProgress RunBatchLocally(const BatchSpec& spec, const std::vector<BatchRun>& runs,
                              const std::vector<BatchRun>& pending, const std::string& out_dir,
                              const LocalBatchOptions& options);

/// Submits the pending runs as a Slurm job array (`sbatch`; one task per `runs_per_task` runs,
/// each task `trav batch-task`), and with `options.wait` waits until `squeue` no longer lists it,
/// then writes the report. Returns the job id. @throws std::runtime_error if sbatch fails.
std::string SubmitBatchToSlurm(const std::vector<BatchRun>& runs,
                               const std::vector<BatchRun>& pending, const std::string& out_dir,
                               const SlurmOptions& options);

/// A Slurm array task's side: runs the runs of task `index` listed in `tasks_file` (written by
/// SubmitBatchToSlurm) one after the other, skipping finished ones, recording each end.
void RunBatchTask(const std::string& tasks_file, int index, const std::string& trav_executable);

/// Writes the report of the batch in `out_dir` from whatever has finished (batch.json lists the
/// runs): results.csv, results.json, report.md and plots (WriteBatchReport). Returns how many
/// runs have a result. @throws common::InputError if `out_dir` has no batch.json.
int CollectBatch(const std::string& out_dir);

/// Records how a run's process ended: finished if it wrote runs/<id>/summary.json (removing an
/// older failure record), else failed/<id>.json with the outcome crashed, killed, timed_out or
/// error. Returns true if it finished.
bool RecordRunEnd(const std::string& out_dir, const std::string& id, const ProcessResult& end);

}  // namespace trav::scenarios
