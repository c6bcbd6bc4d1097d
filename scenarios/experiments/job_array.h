#pragma once

#include <optional>
#include <string>
#include <vector>

#include "scenarios/run/process_pool.h"

namespace trav::scenarios {

/// One independent job of a batch or an evaluation: a command that writes one result file
/// atomically. The job is finished when its result exists; running it again is never needed.
struct Job {
  std::string id;                 ///< unique in its folder; names failed/<id>.json
  std::vector<std::string> argv;  ///< the command
  std::string log_path;           ///< its standard output and error
  std::string result_path;        ///< the file it writes when it finishes
};

/// How the jobs of one call ended.
struct JobsProgress {
  int finished{0};  ///< wrote their result
  int failed{0};    ///< crashed, killed, timed out or ended without a result
  bool interrupted{false};
};

/// Records how a job's process ended in `folder`: finished if its result exists (removing an
/// older failed/<id>.json), else failed/<id>.json (written atomically) with the outcome crashed
/// (a signal other than SIGKILL, or exit code 3), killed (SIGKILL: out of memory or killed from
/// outside), timed_out, or error (any other end), the process's end, exit code, signal, wall time
/// and log. Returns true if it finished.
bool RecordJobEnd(const std::string& folder, const Job& job, const ProcessResult& end);

/// Runs `jobs` as local processes, `parallel` at a time, each limited to `time_limit_s`,
/// recording each end (RecordJobEnd) and reporting it to `progress` (unless null). SIGINT or
/// SIGTERM stops the running jobs (their results are lost, the others kept).
JobsProgress RunJobsLocally(const std::string& folder, const std::vector<Job>& jobs, int parallel,
                            double time_limit_s, ProgressLine* progress);

/// Settings of a Slurm submission.
struct SlurmOptions {
  std::string partition;        ///< empty: the cluster's default
  std::string time;             ///< per array task ("HH:MM:SS"), empty: the partition's default
  int jobs_per_task{1};         ///< jobs per array task, >= 1
  bool wait{true};              ///< wait until the job array has ended
  std::string trav_executable;  ///< the `trav` the tasks run (on a filesystem the nodes share)
};

/// Checks Slurm options against strict patterns (a partition name, a Slurm time format, a job
/// count), so that no value can carry anything else to sbatch. @throws common::InputError naming
/// the option.
void ValidateSlurmOptions(const SlurmOptions& options);

/// Submits `jobs` as one Slurm job array (`sbatch`): `options.jobs_per_task` jobs per array task,
/// each task `trav job-task <folder>/slurm/tasks-<n>.json <index>` running its jobs one after the
/// other with `time_limit_s` each (slurm/job-<n>.sh is the script, logs/slurm-<job>_<task>.out the
/// tasks' output). With `options.wait`, returns when `squeue` no longer lists the job, printing the
/// jobs finished as they appear. Returns the Slurm job id.
/// @throws std::runtime_error if sbatch is missing or refuses the job.
std::string SubmitJobArray(const std::string& folder, const std::vector<Job>& jobs,
                           double time_limit_s, const SlurmOptions& options);

/// A job of `folder` with its log at <folder>/logs/<id>.log.
Job FolderJob(const std::string& folder, const std::string& id, std::vector<std::string> argv,
              std::string result_path);

/// Where a campaign's jobs run.
struct JobDispatch {
  int parallel{1};                    ///< local processes at a time, >= 1
  std::optional<SlurmOptions> slurm;  ///< set: one Slurm job array instead of local processes
  ProgressLine* progress{nullptr};    ///< told of each local job's end (may be null)
};

/// How a dispatch ended.
struct DispatchEnd {
  JobsProgress jobs;      ///< with Slurm counted from the results once the array has ended
  std::string slurm_job;  ///< the job array's id (Slurm only)
  bool waited{true};      ///< false: submitted to Slurm without waiting, nothing counted yet
};

/// Runs `jobs` in `folder` as `dispatch` says (RunJobsLocally or SubmitJobArray): the one way
/// eval, batch and tune run their jobs. Nothing to run returns at once.
/// @throws std::runtime_error if sbatch is missing or refuses the job.
DispatchEnd DispatchJobs(const std::string& folder, const std::vector<Job>& jobs,
                         double time_limit_s, const JobDispatch& dispatch);

/// One array task of a Slurm tasks file.
struct JobTask {
  std::string folder;        ///< the batch or evaluation folder the jobs write into
  double time_limit_s{0.0};  ///< per job [s]
  std::vector<Job> jobs;
};

/// Reads task `index` of `tasks_file`, accepting only trav's own jobs: `trav_executable` with the
/// subcommand run or eval-scene, a safe id, and log and result files inside the folder (a tasks
/// file is data, never a way to run any command).
/// @throws common::InputError naming the file if it is malformed or holds another job.
JobTask ReadJobTask(const std::string& tasks_file, int index, const std::string& trav_executable);

/// The array task's side: runs the jobs of task `index` in `tasks_file` that have no result yet,
/// one after the other, recording each end in the folder the file belongs to.
/// @throws common::InputError if the file cannot be read or has no such task.
void RunJobTask(const std::string& tasks_file, int index);

/// True if the file exists (a finished job's result).
bool ResultExists(const std::string& path);

}  // namespace trav::scenarios
