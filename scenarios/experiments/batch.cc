#include "scenarios/experiments/batch.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <utility>

#include <nlohmann/json.hpp>

#include "common/input_error.h"
#include "common/logging.h"
#include "common/yaml_reader.h"
#include "scenarios/experiments/batch_report.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/scenario.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

// Sweep keys that stand for a scenario key.
constexpr std::pair<const char*, const char*> kShorthands[] = {
    {"seed", "terrain.seed"},         {"terrain", "terrain.type"},
    {"mapper", "mapping.method"},     {"mover_count", "traffic.count"},
    {"mover_speed", "traffic.speed"}, {"mover_behaviour", "traffic.behaviour"},
    {"mover_shape", "traffic.shape"}};

bool Finished(const fs::path& folder, const std::string& id) {
  return ResultExists((folder / "runs" / id / "summary.json").string());
}

// The `trav run` jobs of runs.
std::vector<Job> RunJobs(const fs::path& folder, const std::vector<BatchRun>& runs,
                         const std::string& trav) {
  std::vector<Job> jobs;
  for (const BatchRun& run : runs) {
    jobs.push_back(FolderJob(folder.string(), run.id,
                             {trav, "run", (folder / "scenarios" / (run.id + ".yaml")).string(),
                              "--out", (folder / "runs" / run.id).string()},
                             (folder / "runs" / run.id / "summary.json").string()));
  }
  return jobs;
}

}  // namespace

void to_json(nlohmann::json& json, const BatchRunEntry& entry) {
  json = {{"id", entry.id}, {"scenario", entry.scenario}, {"parameters", entry.parameters}};
}

void from_json(const nlohmann::json& json, BatchRunEntry& entry) {
  json.at("id").get_to(entry.id);
  json.at("scenario").get_to(entry.scenario);
  json.at("parameters").get_to(entry.parameters);
}

RunFileHeader ReadRunFileHeader(common::YamlReader* root, const std::string& path) {
  RunFileHeader header;
  header.name = fs::path(path).stem().string();
  int schema_version = 1;
  root->Read("schema_version", &schema_version);
  root->Check("schema_version", schema_version == 1, "is not supported (expected 1)");
  root->Read("name", &header.name);
  root->Read("scenarios", &header.scenarios);
  root->Check("scenarios", !header.scenarios.empty(), "must list at least one scenario file");
  const fs::path base = fs::path(path).parent_path();
  for (std::string& scenario : header.scenarios) {
    if (fs::path(scenario).is_relative()) scenario = (base / scenario).lexically_normal().string();
  }
  if (root->Has("set")) {
    common::YamlReader sets = root->Map("set");
    for (const std::string& key : sets.Keys()) {
      std::string value;
      sets.ReadText(key, &value);
      header.sets.push_back(key + "=" + value);
    }
    sets.Finish();
  }
  return header;
}

BatchSpec LoadBatchFile(const std::string& path) {
  const common::YamlDocument document = common::YamlDocument::Load(path);
  common::YamlReader root = document.Root();
  BatchSpec spec;
  spec.source = path;
  RunFileHeader header = ReadRunFileHeader(&root, path);
  spec.name = std::move(header.name);
  spec.scenarios = std::move(header.scenarios);
  spec.sets = std::move(header.sets);
  if (root.Has("sweep")) {
    common::YamlReader sweep = root.Map("sweep");
    for (const auto& [label, key_path] : kShorthands) {
      if (!sweep.Has(label)) continue;
      SweepAxis axis{label, key_path, {}};
      sweep.Read(label, &axis.values);
      sweep.Check(label, !axis.values.empty(), "must list at least one value");
      spec.axes.push_back(std::move(axis));
    }
    if (sweep.Has("seeds")) {
      common::YamlReader seeds = sweep.Map("seeds");
      int first = 1, count = 0;
      seeds.ReadRequired("first", &first);
      seeds.ReadRequired("count", &count);
      seeds.Check("count", count >= 1 && count <= 100000, "must be in [1, 100000]");
      seeds.Finish();
      SweepAxis axis{"seed", "terrain.seed", {}};
      for (int k = 0; k < count; ++k) axis.values.push_back(std::to_string(first + k));
      spec.axes.push_back(std::move(axis));
    }
    if (sweep.Has("parameters")) {
      common::YamlReader parameters = sweep.Map("parameters");
      for (const std::string& key : parameters.Keys()) {
        SweepAxis axis{key, key, {}};
        parameters.Read(key, &axis.values);
        parameters.Check(key, !axis.values.empty(), "must list at least one value");
        spec.axes.push_back(std::move(axis));
      }
      parameters.Finish();
    }
    sweep.Finish();
    std::set<std::string> keys;
    for (const SweepAxis& axis : spec.axes) {
      if (!keys.insert(axis.key_path).second) {
        sweep.Fail(axis.label, "sweeps " + axis.key_path + " a second time");
      }
    }
  }
  root.Read("time_limit", &spec.time_limit_s);
  root.Check("time_limit", spec.time_limit_s > 0.0 && spec.time_limit_s <= 1e6,
             "must be in (0, 1e6] s");
  root.Finish();
  return spec;
}

std::vector<BatchRun> ExpandBatch(const BatchSpec& spec) {
  double total = static_cast<double>(spec.scenarios.size());
  for (const SweepAxis& axis : spec.axes) total *= static_cast<double>(axis.values.size());
  if (total > kMaxBatchRuns) {
    throw common::InputError(spec.source, "sweep",
                             "gives more runs than the 100000 one batch holds");
  }
  std::vector<BatchRun> runs;
  std::set<std::string> ids;
  for (const std::string& base : spec.scenarios) {
    // every combination of the axes' values, the last axis fastest
    std::vector<std::size_t> choice(spec.axes.size(), 0);
    while (true) {
      BatchRun run;
      Scenario scenario;
      try {
        common::YamlDocument document = common::YamlDocument::Load(base);
        ApplyOverrides(spec.sets, &document);
        for (std::size_t a = 0; a < spec.axes.size(); ++a) {
          const std::string& value = spec.axes[a].values[choice[a]];
          document.Set(spec.axes[a].key_path, value);
          run.parameters.emplace_back(spec.axes[a].label, value);
        }
        scenario = LoadScenario(document);
      } catch (const common::InputError& e) {
        throw common::InputError(spec.source, "", std::string("a run of the batch: ") + e.what());
      }
      run.scenario_name = scenario.name;
      std::string id = scenario.name;
      for (const auto& [label, value] : run.parameters) id += "_" + label + "-" + value;
      run.id = SafeFileName(id);
      if (!ids.insert(run.id).second) {
        throw common::InputError(
            spec.source, "",
            "two runs get the id '" + run.id + "' (give the scenarios different names)");
      }
      run.scenario_yaml = ResolvedScenarioYaml(scenario);
      runs.push_back(std::move(run));

      std::size_t a = spec.axes.size();
      while (a > 0 && ++choice[a - 1] == spec.axes[a - 1].values.size()) choice[--a] = 0;
      if (a == 0) break;
    }
  }
  return runs;
}

std::vector<BatchRun> PrepareBatchFolder(const BatchSpec& spec, const std::vector<BatchRun>& runs,
                                         const CampaignFolder& campaign) {
  const fs::path folder(campaign.path());
  std::vector<BatchRunEntry> entries;
  for (const BatchRun& run : runs) {
    BatchRunEntry& entry = entries.emplace_back(BatchRunEntry{run.id, run.scenario_name, {}});
    for (const auto& [label, value] : run.parameters) entry.parameters[label] = value;
  }
  nlohmann::json batch = {{"name", spec.name},
                          {"source", spec.source},
                          {"time_limit_s", spec.time_limit_s},
                          {"runs", entries}};
  campaign.Claim(
      batch,
      [&](const nlohmann::json& previous) {
        // the same runs, and every scenario written so far the same (a batch killed while laying
        // out its folder may lack some)
        bool same = previous.value("runs", nlohmann::json()) == batch["runs"];
        for (const BatchRun& run : runs) {
          const fs::path scenario = folder / "scenarios" / (run.id + ".yaml");
          std::error_code missing;
          same = same && (!fs::exists(scenario, missing) ||
                          ReadTextFile(scenario.string()) == run.scenario_yaml);
        }
        return same;
      },
      "the folder holds another batch (other runs or scenarios); use another --out, or the same "
      "batch to resume it");
  std::error_code error;
  for (const char* sub : {"scenarios", "runs", "logs", "failed", "slurm"}) {
    fs::create_directories(folder / sub);
  }
  for (const BatchRun& run : runs) {
    const fs::path scenario = folder / "scenarios" / (run.id + ".yaml");
    if (!fs::exists(scenario, error)) WriteTextFileAtomically(scenario.string(), run.scenario_yaml);
  }
  std::vector<BatchRun> pending;
  for (const BatchRun& run : runs) {
    if (!Finished(folder, run.id)) pending.push_back(run);
  }
  return pending;
}

BatchProgress RunBatchLocally(const BatchSpec& spec, const std::vector<BatchRun>& runs,
                              const std::vector<BatchRun>& pending, const std::string& out_dir,
                              const LocalBatchOptions& options) {
  const fs::path folder = fs::absolute(out_dir);
  const int resumed = static_cast<int>(runs.size() - pending.size());
  if (resumed > 0) {
    common::LogStream(common::LogLevel::kInfo)
        << resumed << " of " << runs.size() << " runs already finished in " << out_dir << ": kept";
  }
  ProgressLine progress(static_cast<int>(runs.size()), resumed, "run", options.progress_bar);
  const JobsProgress jobs =
      DispatchJobs(folder.string(), RunJobs(folder, pending, options.trav_executable),
                   spec.time_limit_s, {options.jobs, std::nullopt, &progress})
          .jobs;
  BatchProgress result;
  result.finished = jobs.finished;
  result.failed = jobs.failed;
  result.interrupted = jobs.interrupted;
  result.runs = static_cast<int>(runs.size());
  result.resumed = resumed;
  if (!result.interrupted) WriteBatchReport(folder.string());
  return result;
}

std::string SubmitBatchToSlurm(const BatchSpec& spec, const std::vector<BatchRun>& pending,
                               const std::string& out_dir, const SlurmOptions& options) {
  const fs::path folder = fs::absolute(out_dir);
  const DispatchEnd end =
      DispatchJobs(folder.string(), RunJobs(folder, pending, options.trav_executable),
                   spec.time_limit_s, {1, options, nullptr});
  if (end.waited) WriteBatchReport(folder.string());
  return end.slurm_job;
}

int CollectBatch(const std::string& out_dir) {
  const fs::path folder = fs::absolute(out_dir);
  const nlohmann::json batch = ReadJsonFile((folder / "batch.json").string());
  int finished = 0;
  for (const BatchRunEntry& run : batch.at("runs").get<std::vector<BatchRunEntry>>()) {
    finished += Finished(folder, run.id) ? 1 : 0;
  }
  WriteBatchReport(folder.string());
  return finished;
}

}  // namespace trav::scenarios
