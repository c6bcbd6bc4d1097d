#pragma once

#include <map>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace trav::scenarios {

/// Every number (and boolean, as 0 or 1) of a summary.json, keyed by its dotted path
/// ("navigation.time_to_goal_s", "tracking.rms_lateral_error_m"); arrays and strings are left out.
std::map<std::string, double> FlattenSummary(const nlohmann::json& summary);

/// One row of a batch's results.json: a run with a result (a summary, or the record of a failure).
struct BatchResult {
  std::string id;
  std::string scenario;                           ///< the scenario's name
  std::map<std::string, std::string> parameters;  ///< label: value, per swept parameter
  std::string outcome;
  bool success{false};                    ///< the run ended as its scenario expects
  std::map<std::string, double> metrics;  ///< FlattenSummary of its summary.json
};

/// results.json's object of a run, and back. @throws nlohmann::json::exception on a missing field
/// or a field of another type.
void to_json(nlohmann::json& json, const BatchResult& result);
void from_json(const nlohmann::json& json, BatchResult& result);

/// A binomial proportion's 95 % Wilson score interval.
struct WilsonInterval {
  double low{0.0};
  double high{0.0};
};
/// The interval of `successes` out of `trials` (trials > 0; [0, 1] when there are none).
WilsonInterval Wilson95(int successes, int trials);

/// Writes the report of the batch in `out_dir` (batch.json, runs/<id>/summary.json,
/// failed/<id>.json), each file atomically:
/// - results.json (BatchResult) and results.csv: one row per run with a result or a failure
///   record: id, scenario, each swept parameter, outcome, success (the run ended as its scenario
///   expects), and every numeric value of its summary.json (flattened:
///   "navigation.time_to_goal_s");
/// - report.md: runs per outcome; per group of runs (the same scenario and parameters but seeds:
///   any label ending in "seed"), in batch order, the success rate with its 95 % Wilson interval
///   and the median and 10th-90th percentiles of time to goal, path length ratio, smallest mover
///   clearance, near misses, max roll and pitch, RMS lateral tracking error, mapping update and
///   real-time factor; the failed runs with their logs;
/// - for each swept parameter with two or more numeric values (but seeds): vs_<label>.csv,
///   success_vs_<label>.png (success rate with its interval as a band, collision rate),
///   time_vs_<label>.png (median time to goal and path length ratio of successful runs),
///   clearance_vs_<label>.png (median smallest mover clearance) and replans_vs_<label>.png (median
///   plans per simulated second), the medians with their 10th-90th percentile bands, against it,
///   over all other parameters; each plot also as SVG;
/// - contact_sheet.html and contact_sheet.png (WriteContactSheet), linked from report.md.
/// Runs without a result yet are counted as pending.
void WriteBatchReport(const std::string& out_dir);

}  // namespace trav::scenarios
