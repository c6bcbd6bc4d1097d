#include "scenarios/experiments/batch_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/input_error.h"
#include "common/statistics.h"
#include "common/text.h"
#include "scenarios/experiments/batch.h"
#include "scenarios/experiments/contact_sheet.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/plots.h"
#include "scenarios/run/run_metrics.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

// One run's row, with the log of a run that failed to finish.
struct Row : BatchResult {
  std::string log;  // failed runs only
};

// The metrics of the group table: summary key, column title, successful runs only.
struct MetricColumn {
  const char* key;
  const char* title;
  bool success_only;
};
constexpr MetricColumn kGroupMetrics[] = {
    {"navigation.time_to_goal_s", "time to goal [s]", true},
    {"navigation.path_length_ratio", "path ratio", true},
    {"navigation.min_mover_clearance_m", "min mover clearance [m]", false},
    {"navigation.near_misses", "near misses", false},
    {"max_roll_deg", "max roll [deg]", false},
    {"max_pitch_deg", "max pitch [deg]", false},
    {"tracking.rms_lateral_error_m", "RMS lateral error [m]", false},
    {"mapping.update_ms_median", "mapping update [ms]", false},
    {"real_time_factor", "real-time factor", false},
};

// "median (p10 to p90)" of a metric over rows, or "-".
std::string Spread(const std::vector<const Row*>& rows, const MetricColumn& column) {
  std::vector<double> values;
  for (const Row* row : rows) {
    if (column.success_only && !row->success) continue;
    const auto it = row->metrics.find(column.key);
    if (it != row->metrics.end() && std::isfinite(it->second)) values.push_back(it->second);
  }
  if (values.empty()) return "-";
  return common::FormatNumber("%.3g", common::Quantile(values, 0.5)) + " (" +
         common::FormatNumber("%.3g", common::Quantile(values, 0.1)) + "-" +
         common::FormatNumber("%.3g", common::Quantile(values, 0.9)) + ")";
}

std::optional<double> Number(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') return std::nullopt;
  return value;
}

// The success count of rows, and the rate with its interval as text.
std::string SuccessText(const std::vector<const Row*>& rows) {
  int successes = 0;
  for (const Row* row : rows) successes += row->success ? 1 : 0;
  const WilsonInterval interval = Wilson95(successes, static_cast<int>(rows.size()));
  return common::FormatNumber("%.0f %%", 100.0 * successes / static_cast<double>(rows.size())) +
         " (" + common::FormatNumber("%.0f", 100.0 * interval.low) + "-" +
         common::FormatNumber("%.0f", 100.0 * interval.high) + ")";
}

// vs_<label>.csv and its plots for a numeric swept parameter; returns the images written.
std::vector<std::string> ParameterPlots(const fs::path& folder, const std::string& label,
                                        const std::vector<Row>& rows,
                                        std::vector<std::string>* notes) {
  std::map<double, std::vector<const Row*>> by_value;
  for (const Row& row : rows) {
    for (const auto& [l, value] : row.parameters) {
      if (l == label) by_value[*Number(value)].push_back(&row);
    }
  }
  std::string csv =
      "value,success_rate,ci_low,ci_high,collision_rate,time_to_goal_median,path_ratio_median,"
      "min_clearance_median,replans_per_s_median,time_to_goal_p10,time_to_goal_p90,"
      "path_ratio_p10,path_ratio_p90,min_clearance_p10,min_clearance_p90,replans_per_s_p10,"
      "replans_per_s_p90\n";
  for (const auto& [value, group] : by_value) {
    int successes = 0, collisions = 0;
    std::vector<double> times, ratios, clearances, replan_rates;
    for (const Row* row : group) {
      successes += row->success ? 1 : 0;
      collisions += row->outcome == "collision" ? 1 : 0;
      const auto metric = [&](const char* key) -> std::optional<double> {
        const auto it = row->metrics.find(key);
        if (it == row->metrics.end()) return std::nullopt;
        return it->second;
      };
      if (const auto clearance = metric("navigation.min_mover_clearance_m")) {
        clearances.push_back(*clearance);
      }
      const auto plans = metric("navigation.plans");
      const auto sim_time = metric("sim_time_s");
      if (plans && sim_time && *sim_time > 0.0) replan_rates.push_back(*plans / *sim_time);
      if (!row->success) continue;
      if (const auto time = metric("navigation.time_to_goal_s")) times.push_back(*time);
      if (const auto ratio = metric("navigation.path_length_ratio")) ratios.push_back(*ratio);
    }
    const double n = static_cast<double>(group.size());
    const WilsonInterval interval = Wilson95(successes, static_cast<int>(group.size()));
    auto quantile = [](const std::vector<double>& values, double q) {
      return values.empty() ? std::string()
                            : common::FormatNumber("%.6g", common::Quantile(values, q));
    };
    csv += common::FormatNumber("%.6g", value) + "," + common::FormatNumber("%.6g", successes / n) +
           "," + common::FormatNumber("%.6g", interval.low) + "," +
           common::FormatNumber("%.6g", interval.high) + "," +
           common::FormatNumber("%.6g", collisions / n);
    for (const std::vector<double>* values : {&times, &ratios, &clearances, &replan_rates}) {
      csv += "," + quantile(*values, 0.5);
    }
    for (const std::vector<double>* values : {&times, &ratios, &clearances, &replan_rates}) {
      csv += "," + quantile(*values, 0.1) + "," + quantile(*values, 0.9);
    }
    csv += "\n";
  }
  const std::string name = "vs_" + label;
  const std::string csv_path = (folder / (name + ".csv")).string();
  WriteTextFileAtomically(csv_path, csv);
  const std::string spread = "10th-90th percentile of runs";
  const std::vector<LinePlot> plots = {
      {"success_vs_" + label + ".png",
       "Success and collision rates against " + label,
       "value",
       label,
       "fraction of runs",
       {{"success_rate", "success rate", "ci_low", "ci_high", "95 % Wilson interval of success"},
        {"collision_rate", "collision rate"}},
       true},
      {"time_vs_" + label + ".png",
       "Time to goal and path length ratio against " + label + " (successful runs)",
       "value",
       label,
       "time to goal [s] / path length ratio",
       {{"time_to_goal_median", "median time to goal [s]", "time_to_goal_p10", "time_to_goal_p90",
         "time to goal, " + spread},
        {"path_ratio_median", "median path length ratio", "path_ratio_p10", "path_ratio_p90",
         "path length ratio, " + spread}},
       true},
      {"clearance_vs_" + label + ".png",
       "Smallest gap to a mover against " + label,
       "value",
       label,
       "min mover clearance [m]",
       {{"min_clearance_median", "median min mover clearance", "min_clearance_p10",
         "min_clearance_p90", spread}},
       false},
      {"replans_vs_" + label + ".png",
       "Plans per second against " + label,
       "value",
       label,
       "plans per simulated second",
       {{"replans_per_s_median", "median plans per second", "replans_per_s_p10",
         "replans_per_s_p90", spread}},
       true}};
  const PlotResult result = WriteLinePlots(csv_path, plots, folder.string());
  if (!result.message.empty()) notes->push_back(result.message);
  return result.written;
}

}  // namespace

namespace {

void FlattenInto(const nlohmann::json& json, const std::string& prefix,
                 std::map<std::string, double>* out) {
  for (auto it = json.begin(); it != json.end(); ++it) {
    const std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    if (it->is_object()) {
      FlattenInto(*it, key, out);
    } else if (it->is_number()) {
      (*out)[key] = it->get<double>();
    } else if (it->is_boolean()) {
      (*out)[key] = it->get<bool>() ? 1.0 : 0.0;
    }
  }
}

// Seeds (terrain.seed as "seed", traffic.seed, ...) vary runs within a group; they are not
// compared.
bool IsSeedLabel(const std::string& label) {
  return label.size() >= 4 && label.compare(label.size() - 4, 4, "seed") == 0;
}

// The batch's runs that have a result (a summary, or the record of a failure), in the batch's
// order; `labels` receives the swept parameters' names and `pending` the runs without a result.
std::vector<Row> ReadRows(const fs::path& folder, const nlohmann::json& batch,
                          std::vector<std::string>* labels, int* pending) {
  std::vector<Row> rows;
  for (const BatchRunEntry& run : batch.at("runs").get<std::vector<BatchRunEntry>>()) {
    Row row;
    row.id = run.id;
    row.scenario = run.scenario;
    row.parameters = run.parameters;
    for (const auto& [label, value] : run.parameters) {
      if (std::find(labels->begin(), labels->end(), label) == labels->end()) {
        labels->push_back(label);
      }
    }
    if (const auto summary =
            ReadJsonIfPresent((folder / "runs" / row.id / "summary.json").string())) {
      row.outcome = summary->value("outcome", "");
      row.success = row.outcome == summary->value("expected_outcome", "");
      row.metrics = FlattenSummary(*summary);
    } else if (const auto failure =
                   ReadJsonIfPresent((folder / "failed" / (row.id + ".json")).string())) {
      row.outcome = failure->value("outcome", "error");
      row.log = failure->value("log", "");
    } else {
      ++*pending;
      continue;
    }
    rows.push_back(std::move(row));
  }

  return rows;
}

// results.json and results.csv: every run with its parameters, outcome and flattened metrics.
void WriteResults(const fs::path& folder, const std::vector<Row>& rows,
                  const std::vector<std::string>& labels) {
  std::set<std::string> metric_keys;
  for (const Row& row : rows) {
    for (const auto& [key, value] : row.metrics) metric_keys.insert(key);
  }
  std::vector<BatchResult> results;
  std::string csv = "id,scenario";
  for (const std::string& label : labels) csv += "," + label;
  csv += ",outcome,success";
  for (const std::string& key : metric_keys) csv += "," + key;
  csv += "\n";
  for (const Row& row : rows) {
    BatchResult& result = results.emplace_back(
        BatchResult{row.id, row.scenario, {}, row.outcome, row.success, row.metrics});
    csv += row.id + "," + row.scenario;
    for (const std::string& label : labels) {
      const auto it = row.parameters.find(label);
      const std::string value = it == row.parameters.end() ? std::string() : it->second;
      result.parameters[label] = value;
      csv += "," + (value.find(',') == std::string::npos ? value : "\"" + value + "\"");
    }
    csv += "," + row.outcome + "," + (row.success ? "1" : "0");
    for (const std::string& key : metric_keys) {
      const auto it = row.metrics.find(key);
      csv += "," +
             (it == row.metrics.end() ? std::string() : common::FormatNumber("%.9g", it->second));
    }
    csv += "\n";
  }
  WriteTextFileAtomically((folder / "results.json").string(),
                          nlohmann::json(results).dump(1) + "\n");
  WriteTextFileAtomically((folder / "results.csv").string(), csv);
}

// The report's groups: runs of one scenario and parameter values but the seeds, in the order of
// their first run, with the success rate and the spread of each metric.
std::string GroupsSection(const std::vector<Row>& rows) {
  std::ostringstream md;
  std::vector<std::pair<std::string, std::vector<const Row*>>> groups;
  for (const Row& row : rows) {
    std::string group = row.scenario;
    for (const auto& [label, value] : row.parameters) {
      if (!IsSeedLabel(label)) group += ", " + label + "=" + value;
    }
    const auto it = std::find_if(groups.begin(), groups.end(),
                                 [&](const auto& entry) { return entry.first == group; });
    if (it == groups.end()) {
      groups.emplace_back(group, std::vector<const Row*>{&row});
    } else {
      it->second.push_back(&row);
    }
  }
  md << "\n## Groups\n\nSuccess: the run ended as its scenario expects; rate with its 95 % Wilson "
        "interval. Other columns: median (10th-90th percentile); times and path ratios of "
        "successful runs only.\n\n| group | runs | success |";
  for (const MetricColumn& column : kGroupMetrics) md << " " << column.title << " |";
  md << "\n|---|---|---|";
  for (std::size_t i = 0; i < std::size(kGroupMetrics); ++i) md << "---|";
  md << "\n";
  for (const auto& [group, members] : groups) {
    md << "| " << group << " | " << members.size() << " | " << SuccessText(members) << " |";
    for (const MetricColumn& column : kGroupMetrics) md << " " << Spread(members, column) << " |";
    md << "\n";
  }
  return md.str();
}

// The report's table of the runs that failed to finish, with their logs.
std::string FailedRunsSection(const std::vector<Row>& rows) {
  std::ostringstream md;
  bool any_failed = false;
  for (const Row& row : rows) {
    if (row.log.empty()) continue;
    if (!any_failed) md << "\n## Failed runs\n\n| run | outcome | log |\n|---|---|---|\n";
    any_failed = true;
    md << "| " << row.id << " | " << row.outcome << " | " << row.log << " |\n";
  }

  return md.str();
}

// The report's plots against each numeric swept parameter, and their notes.
std::string PlotsSection(const fs::path& folder, const std::vector<Row>& rows,
                         const std::vector<std::string>& labels) {
  std::ostringstream md;
  std::vector<std::string> notes;
  for (const std::string& label : labels) {
    if (IsSeedLabel(label)) continue;
    std::set<double> values;
    bool numeric = true;
    for (const Row& row : rows) {
      for (const auto& [l, value] : row.parameters) {
        if (l != label) continue;
        const std::optional<double> number = Number(value);
        numeric = numeric && number.has_value();
        if (number) values.insert(*number);
      }
    }
    if (!numeric || values.size() < 2) continue;
    md << "\n";
    for (const std::string& image : ParameterPlots(folder, label, rows, &notes)) {
      md << "![" << image << "](" << image << ")\n";
    }
  }
  for (const std::string& note : notes) md << "\n" << note << "\n";
  return md.str();
}

}  // namespace

void to_json(nlohmann::json& json, const BatchResult& result) {
  json = {
      {"id", result.id},           {"scenario", result.scenario}, {"parameters", result.parameters},
      {"outcome", result.outcome}, {"success", result.success},   {"metrics", result.metrics}};
}

void from_json(const nlohmann::json& json, BatchResult& result) {
  json.at("id").get_to(result.id);
  json.at("scenario").get_to(result.scenario);
  json.at("parameters").get_to(result.parameters);
  json.at("outcome").get_to(result.outcome);
  json.at("success").get_to(result.success);
  json.at("metrics").get_to(result.metrics);
}

std::map<std::string, double> FlattenSummary(const nlohmann::json& summary) {
  std::map<std::string, double> values;
  FlattenInto(summary, "", &values);
  return values;
}

WilsonInterval Wilson95(int successes, int trials) {
  if (trials <= 0) return {0.0, 1.0};
  constexpr double z = 1.959963984540054;
  const double n = trials;
  const double p = successes / n;
  const double denominator = 1.0 + z * z / n;
  const double centre = (p + z * z / (2.0 * n)) / denominator;
  const double half = z * std::sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n)) / denominator;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

void WriteBatchReport(const std::string& out_dir) {
  const fs::path folder(out_dir);
  const std::optional<nlohmann::json> batch = ReadJsonIfPresent((folder / "batch.json").string());
  if (!batch) throw common::InputError((folder / "batch.json").string(), "", "no batch here");
  std::vector<std::string> labels;
  int pending = 0;
  const std::vector<Row> rows = ReadRows(folder, *batch, &labels, &pending);
  WriteResults(folder, rows, labels);

  // report.md
  const std::size_t finished = static_cast<std::size_t>(
      std::count_if(rows.begin(), rows.end(), [](const Row& row) { return row.log.empty(); }));
  std::ostringstream md;
  md << "# Batch " << batch->value("name", "") << "\n\n"
     << batch->at("runs").size() << " runs: " << finished << " finished, " << rows.size() - finished
     << " failed to finish, " << pending << " pending. Source: `" << batch->value("source", "")
     << "`.\n\n| outcome | runs |\n|---|---|\n";
  std::map<std::string, int> outcomes;
  for (const Row& row : rows) ++outcomes[row.outcome];
  for (const auto& [outcome, count] : outcomes) md << "| " << outcome << " | " << count << " |\n";
  md << GroupsSection(rows) << FailedRunsSection(rows) << PlotsSection(folder, rows, labels);
  const std::vector<std::string> sheet =
      WriteContactSheet(out_dir, std::vector<BatchResult>(rows.begin(), rows.end()));
  md << "\n## Contact sheet\n\nOne thumbnail per run, its outcome's colour round it, linked to "
        "its video: [contact_sheet.html](contact_sheet.html).\n";
  if (std::find(sheet.begin(), sheet.end(), "contact_sheet.png") != sheet.end()) {
    md << "\n![contact sheet](contact_sheet.png)\n";
  }
  WriteTextFileAtomically((folder / "report.md").string(), md.str());
}

}  // namespace trav::scenarios
