#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "common/yaml_reader.h"
#include "scenarios/experiments/job_array.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/process_pool.h"

namespace trav::scenarios {

/// The most runs one batch holds.
inline constexpr double kMaxBatchRuns = 100000;

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

/// A run as batch.json lists it: its id, scenario name and swept values.
struct BatchRunEntry {
  std::string id;
  std::string scenario;                           ///< the scenario's name
  std::map<std::string, std::string> parameters;  ///< label: value, per axis
};

/// batch.json's object of a run, and back. @throws nlohmann::json::exception on a missing field or
/// a field of another type.
void to_json(nlohmann::json& json, const BatchRunEntry& entry);
void from_json(const nlohmann::json& json, BatchRunEntry& entry);

/// What batch and tuning files share: `schema_version` (1), `name` (default the file's stem),
/// `scenarios` (files resolved against the file's folder, at least one) and `set` (overrides of
/// every run, as key.path=value).
struct RunFileHeader {
  std::string name;
  std::vector<std::string> scenarios;
  std::vector<std::string> sets;
};

/// Reads those keys from the root of the file at `path`. @throws common::InputError naming the
/// file and key.
RunFileHeader ReadRunFileHeader(common::YamlReader* root, const std::string& path);

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

/// The subfolders of a batch folder where a killed run leaves files half-written (for
/// CampaignFolder to remove).
inline const std::vector<std::string> kBatchPartialSubfolders = {"runs", "scenarios", "failed"};

/// Lays out the folder of `campaign` (of kind "batch") for the runs: batch.json (the runs and the
/// limits; the campaign's identity), scenarios/<id>.yaml, runs/, logs/, failed/. Returns the runs
/// not yet finished (no runs/<id>/summary.json). @throws common::InputError if the folder holds
/// another batch (other runs or scenarios).
std::vector<BatchRun> PrepareBatchFolder(const BatchSpec& spec, const std::vector<BatchRun>& runs,
                                         const CampaignFolder& campaign);

/// Runs the pending runs as local `trav run` processes (a crash, a hang past the time limit or a
/// kill of one is recorded as that run's outcome under failed/<id>.json, and the others go on),
/// then writes the report (WriteBatchReport) unless interrupted (SIGINT, SIGTERM: running runs
/// are stopped and lost, finished ones kept).
BatchProgress RunBatchLocally(const BatchSpec& spec, const std::vector<BatchRun>& runs,
                              const std::vector<BatchRun>& pending, const std::string& out_dir,
                              const LocalBatchOptions& options);

/// Submits the pending runs as a Slurm job array (SubmitJobArray: each array task runs
/// `options.jobs_per_task` runs as `trav run` processes), and with `options.wait` writes the report
/// once the job has ended. Returns the job id (empty if nothing was pending).
/// @throws std::runtime_error if sbatch fails.
std::string SubmitBatchToSlurm(const BatchSpec& spec, const std::vector<BatchRun>& pending,
                               const std::string& out_dir, const SlurmOptions& options);

/// Writes the report of the batch in `out_dir` from whatever has finished (batch.json lists the
/// runs): results.csv, results.json, report.md and plots (WriteBatchReport). Returns how many
/// runs have a result. @throws common::InputError if `out_dir` has no batch.json.
int CollectBatch(const std::string& out_dir);

}  // namespace trav::scenarios
