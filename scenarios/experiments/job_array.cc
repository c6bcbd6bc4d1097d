#include "scenarios/experiments/job_array.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

#include <nlohmann/json.hpp>

#include "common/enum_names.h"
#include "common/input_error.h"
#include "common/input_file.h"
#include "common/logging.h"
#include "scenarios/run/output_folder.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

// The outcome recorded for a job that ended without its result.
std::string FailureOutcome(const ProcessResult& end) {
  switch (end.end) {
    case ProcessEnd::kTimedOut:
      return "timed_out";
    case ProcessEnd::kSignaled:
      return end.signal == SIGKILL ? "killed" : "crashed";
    case ProcessEnd::kExited:
      return end.exit_code == 3 ? "crashed" : "error";
    case ProcessEnd::kNotStarted:
    case ProcessEnd::kCancelled:
      return "error";
  }
  return "error";
}

// Text with surrounding whitespace removed.
std::string Trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \n\r\t");
  if (first == std::string::npos) return "";
  const auto last = text.find_last_not_of(" \n\r\t");
  return text.substr(first, last - first + 1);
}

// Quotes a word for /bin/sh.
std::string ShellQuoted(const std::string& word) {
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// True if `path` is inside `folder` (lexically, after removing "." and "..").
bool IsInside(const std::string& path, const std::string& folder) {
  const fs::path relative = fs::path(path).lexically_normal().lexically_relative(folder);
  return !relative.empty() && *relative.begin() != ".." &&
         fs::path(path).is_absolute() == fs::path(folder).is_absolute();
}

nlohmann::json JobJson(const Job& job) {
  return {{"id", job.id}, {"argv", job.argv}, {"log", job.log_path}, {"result", job.result_path}};
}

Job JobFromJson(const nlohmann::json& json) {
  return {json.at("id").get<std::string>(), json.at("argv").get<std::vector<std::string>>(),
          json.at("log").get<std::string>(), json.at("result").get<std::string>()};
}

}  // namespace

bool ResultExists(const std::string& path) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}

bool RecordJobEnd(const std::string& folder, const Job& job, const ProcessResult& end) {
  const fs::path failed_path = fs::path(folder) / "failed" / (job.id + ".json");
  std::error_code error;
  if (ResultExists(job.result_path)) {
    fs::remove(failed_path, error);
    return true;
  }
  const nlohmann::json failure = {
      {"id", job.id},
      {"outcome", FailureOutcome(end)},
      {"end", common::NameOf(end.end)},
      {"exit_code", end.exit_code},
      {"signal", end.signal},
      {"wall_s", end.wall_s},
      {"message", end.message},
      {"log", fs::path(job.log_path).lexically_relative(folder).string()}};
  fs::create_directories(failed_path.parent_path());
  WriteTextFileAtomically(failed_path.string(), failure.dump(1) + "\n");
  return false;
}

JobsProgress RunJobsLocally(const std::string& folder, const std::vector<Job>& jobs, int parallel,
                            double time_limit_s, ProgressLine* progress) {
  std::vector<ProcessTask> tasks;
  for (const Job& job : jobs) tasks.push_back({job.argv, job.log_path});
  JobsProgress result;
  auto on_done = [&](std::size_t index, const ProcessResult& end) {
    if (end.end == ProcessEnd::kCancelled) return;
    const bool finished = RecordJobEnd(folder, jobs[index], end);
    ++(finished ? result.finished : result.failed);
    if (progress != nullptr) progress->Ended(jobs[index].id, finished, end.wall_s);
  };
  const std::vector<ProcessResult> ends = RunProcessPool(tasks, {parallel, time_limit_s}, on_done);
  result.interrupted = std::any_of(ends.begin(), ends.end(), [](const ProcessResult& end) {
    return end.end == ProcessEnd::kCancelled;
  });
  return result;
}

Job FolderJob(const std::string& folder, const std::string& id, std::vector<std::string> argv,
              std::string result_path) {
  return {id, std::move(argv), (fs::path(folder) / "logs" / (id + ".log")).string(),
          std::move(result_path)};
}

DispatchEnd DispatchJobs(const std::string& folder, const std::vector<Job>& jobs,
                         double time_limit_s, const JobDispatch& dispatch) {
  DispatchEnd end;
  if (jobs.empty()) return end;
  if (!dispatch.slurm) {
    end.jobs = RunJobsLocally(folder, jobs, dispatch.parallel, time_limit_s, dispatch.progress);
    return end;
  }
  end.slurm_job = SubmitJobArray(folder, jobs, time_limit_s, *dispatch.slurm);
  end.waited = dispatch.slurm->wait;
  if (!end.waited) return end;
  for (const Job& job : jobs)
    ++(ResultExists(job.result_path) ? end.jobs.finished : end.jobs.failed);
  return end;
}

void ValidateSlurmOptions(const SlurmOptions& options) {
  // Slurm's partition names, and its time formats: minutes, M:S, H:M:S, D-H, D-H:M, D-H:M:S
  static const std::regex kPartition("[A-Za-z0-9_.-]{1,64}(,[A-Za-z0-9_.-]{1,64}){0,15}");
  static const std::regex kTime("(UNLIMITED|INFINITE|([0-9]{1,4}-)?[0-9]{1,6}(:[0-9]{1,2}){0,2})");
  if (!options.partition.empty() && !std::regex_match(options.partition, kPartition)) {
    throw common::InputError("--partition", "",
                             "expected a Slurm partition name (letters, digits, '_', '.', '-'; "
                             "comma-separated), got " +
                                 common::QuotedExcerpt(options.partition));
  }
  if (!options.time.empty() && !std::regex_match(options.time, kTime)) {
    throw common::InputError("--time", "",
                             "expected a Slurm time limit (MM, HH:MM:SS or D-HH:MM:SS), got " +
                                 common::QuotedExcerpt(options.time));
  }
  if (options.jobs_per_task < 1 || options.jobs_per_task > 100000) {
    throw common::InputError("jobs per task", std::to_string(options.jobs_per_task),
                             "must be in [1, 100000]");
  }
}

std::string SubmitJobArray(const std::string& folder_path, const std::vector<Job>& jobs,
                           double time_limit_s, const SlurmOptions& options) {
  ValidateSlurmOptions(options);
  const fs::path folder = fs::absolute(folder_path);
  const fs::path slurm = folder / "slurm";
  fs::create_directories(slurm);
  fs::create_directories(folder / "logs");
  // the tasks: jobs_per_task jobs each
  nlohmann::json tasks = nlohmann::json::array();
  const std::size_t per_task = static_cast<std::size_t>(std::max(1, options.jobs_per_task));
  for (std::size_t i = 0; i < jobs.size(); i += per_task) {
    nlohmann::json task = nlohmann::json::array();
    for (std::size_t j = i; j < std::min(jobs.size(), i + per_task); ++j) {
      task.push_back(JobJson(jobs[j]));
    }
    tasks.push_back(task);
  }
  int submission = 0;
  while (fs::exists(slurm / ("tasks-" + std::to_string(submission) + ".json"))) ++submission;
  const std::string tag = std::to_string(submission);
  const fs::path tasks_path = slurm / ("tasks-" + tag + ".json");
  const nlohmann::json tasks_file = {
      {"folder", folder.string()}, {"time_limit_s", time_limit_s}, {"tasks", tasks}};
  WriteTextFileAtomically(tasks_path.string(), tasks_file.dump(1) + "\n");

  // the job's settings go to sbatch as arguments, never into the script: the script holds one
  // command whose words are quoted, so no path or option can add a line to it
  std::ostringstream script;
  script << "#!/bin/sh\n"
         << "exec " << ShellQuoted(options.trav_executable) << " job-task "
         << ShellQuoted(tasks_path.string()) << " \"$SLURM_ARRAY_TASK_ID\"\n";
  const fs::path script_path = slurm / ("job-" + tag + ".sh");
  WriteTextFileAtomically(script_path.string(), script.str());
  std::vector<std::string> sbatch_argv = {
      "sbatch",
      "--parsable",
      "--job-name=trav",
      "--array=0-" + std::to_string(tasks.size() - 1),
      "--output=" + (folder / "logs" / "slurm-%A_%a.out").string(),
      "--cpus-per-task=1"};
  if (!options.partition.empty()) sbatch_argv.push_back("--partition=" + options.partition);
  if (!options.time.empty()) sbatch_argv.push_back("--time=" + options.time);
  sbatch_argv.push_back(script_path.string());

  const fs::path sbatch_log = slurm / ("sbatch-" + tag + ".log");
  const ProcessResult sbatch = RunProcess({sbatch_argv, sbatch_log.string()});
  const std::string output = Trimmed(ReadTextFile(sbatch_log.string()));
  if (!sbatch.succeeded()) {
    throw std::runtime_error(
        "sbatch failed (" + std::string(common::NameOf(sbatch.end)) + " " +
        std::to_string(sbatch.exit_code) +
        "): " + common::Excerpt(sbatch.message.empty() ? output : sbatch.message, 400));
  }
  const std::string job_id = output.substr(0, output.find(';'));
  if (job_id.empty() || job_id.find_first_not_of("0123456789") != std::string::npos) {
    throw std::runtime_error("sbatch answered " + common::QuotedExcerpt(output) + ", not a job id");
  }
  common::LogStream(common::LogLevel::kInfo)
      << "submitted Slurm job " << job_id << ": " << tasks.size() << " array tasks for "
      << jobs.size() << " jobs (" << script_path << ")";
  if (!options.wait) return job_id;

  // wait until squeue no longer lists the job, reporting finished jobs as they appear
  const fs::path squeue_log = slurm / ("squeue-" + tag + ".log");
  std::size_t reported = 0;
  while (true) {
    std::this_thread::sleep_for(std::chrono::seconds(1));
    std::size_t finished = 0;
    for (const Job& job : jobs) finished += ResultExists(job.result_path) ? 1 : 0;
    if (finished != reported) {
      common::LogStream(common::LogLevel::kInfo)
          << "Slurm job " << job_id << ": " << finished << " of " << jobs.size() << " finished";
      reported = finished;
    }
    const ProcessResult squeue =
        RunProcess({{"squeue", "-h", "-j", job_id, "-o", "%i"}, squeue_log.string()});
    if (!squeue.succeeded() || Trimmed(ReadTextFile(squeue_log.string())).empty()) break;
  }
  return job_id;
}

JobTask ReadJobTask(const std::string& tasks_file, int index, const std::string& trav_executable) {
  const nlohmann::json tasks =
      nlohmann::json::parse(common::ReadInputFile(tasks_file, "Slurm tasks file"), nullptr, false);
  if (tasks.is_discarded() || !tasks.is_object() || !tasks.contains("tasks") ||
      !tasks["tasks"].is_array()) {
    throw common::InputError(tasks_file, "", "is not a Slurm tasks file of trav");
  }
  const nlohmann::json& list = tasks.at("tasks");
  if (index < 0 || static_cast<std::size_t>(index) >= list.size()) {
    throw common::InputError(tasks_file, "", "has no task " + std::to_string(index));
  }
  // only trav's own jobs, writing inside the tasks file's folder: a tasks file is data, and must
  // not be a way to run any command
  JobTask task;
  try {
    task.folder = fs::path(tasks.at("folder").get<std::string>()).lexically_normal().string();
    task.time_limit_s = tasks.at("time_limit_s").get<double>();
    for (const nlohmann::json& job : list[static_cast<std::size_t>(index)]) {
      Job parsed = JobFromJson(job);
      const bool own_command = parsed.argv.size() >= 2 && parsed.argv[0] == trav_executable &&
                               (parsed.argv[1] == "run" || parsed.argv[1] == "eval-scene");
      if (!own_command || SafeFileName(parsed.id) != parsed.id ||
          !IsInside(parsed.log_path, task.folder) || !IsInside(parsed.result_path, task.folder)) {
        throw common::InputError(
            tasks_file, "tasks[" + std::to_string(index) + "]",
            "holds a job that is not one of trav's own (" + common::QuotedExcerpt(parsed.id) + ")");
      }
      task.jobs.push_back(std::move(parsed));
    }
  } catch (const nlohmann::json::exception& e) {
    throw common::InputError(
        tasks_file, "",
        std::string("is not a Slurm tasks file of trav: ") + common::Excerpt(e.what(), 120));
  }
  if (!std::isfinite(task.time_limit_s) || task.time_limit_s <= 0.0 || task.time_limit_s > 1e6) {
    throw common::InputError(tasks_file, "time_limit_s", "must be in (0, 1e6] s");
  }
  return task;
}

void RunJobTask(const std::string& tasks_file, int index) {
  JobTask task = ReadJobTask(tasks_file, index, fs::read_symlink("/proc/self/exe").string());
  std::vector<Job> pending;
  for (Job& job : task.jobs) {
    if (!ResultExists(job.result_path)) pending.push_back(std::move(job));
  }
  RunJobsLocally(task.folder, pending, 1, task.time_limit_s, nullptr);
}

}  // namespace trav::scenarios
