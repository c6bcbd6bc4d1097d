#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "scenarios/experiments/evaluation.h"

namespace trav::scenarios {

/// One method's metrics in one scene, as the report compares them (docs/evaluation.md).
struct SceneMetrics {
  std::string id;  ///< the scene
  std::optional<double> mean_error;
  std::optional<double> auroc;
  std::optional<double> average_precision;
  std::optional<double> spearman;
  /// Mean |f(cost) - truth| over the final map's compared cells, f the isotonic calibration of the
  /// truth on the cost fitted on the method's other scenes (so a method is not punished for its
  /// cost scale); unset without another scene.
  std::optional<double> calibrated_mae;
  std::optional<double> elevation_rmse;
};

/// The metrics SceneMetrics holds, by the names results.json uses, with whether higher is better.
struct MetricName {
  const char* name;
  bool higher_is_better;
};
inline constexpr MetricName kComparedMetrics[] = {
    {"mean_error", false}, {"auroc", true},           {"average_precision", true},
    {"spearman", true},    {"calibrated_mae", false}, {"elevation_rmse", false}};

/// A metric's value by name (kComparedMetrics).
std::optional<double> MetricOf(const SceneMetrics& metrics, const std::string& name);

/// The metrics of `method` in every scene that ran it, in the order of `scenes`, the calibrated
/// error fitted leave-one-scene-out over those scenes.
std::vector<SceneMetrics> MethodSceneMetrics(const std::vector<EvalSceneRecord>& scenes,
                                             const std::string& method);

/// Cells of some scenes per cost bin (HazardScores::cost_truth_histogram): the sum of their truth
/// bins and their count, in integers so that one scene's cells subtract exactly.
using CostTruthSums = std::map<int, std::pair<long long, long long>>;

/// Adds `scene`'s cells to `sums` (sign 1), or takes them out (sign -1).
void AddCells(const HazardScores& scene, int sign, CostTruthSums* sums);

/// The calibrated error of `scene`'s cells under the isotonic fit of truth on cost over the cells
/// of `others` (the other scenes); unset if either has no cell.
std::optional<double> CalibratedMae(const HazardScores& scene, const CostTruthSums& others);

/// The mean over scenes of a method's metric minus the reference method's, on the scenes where
/// both have it, with its 95 % percentile bootstrap interval (2,000 resamples, seeded).
struct PairedDifference {
  std::string metric;
  int scenes{0};
  double mean{0.0};
  double low{0.0};
  double high{0.0};
  /// "better", "worse" (the interval excludes zero, judged by the metric's direction, over at
  /// least 5 scenes) or "not settled".
  std::string verdict;
};

/// results.json's object of a difference, and back.
void to_json(nlohmann::json& json, const PairedDifference& difference);
void from_json(const nlohmann::json& json, PairedDifference& difference);

/// The differences `method` - `reference` for every compared metric over matching scene ids.
std::vector<PairedDifference> PairedDifferences(const std::vector<SceneMetrics>& method,
                                                const std::vector<SceneMetrics>& reference);

/// results.json's object of a scene's metrics (null where unset), and back.
void to_json(nlohmann::json& json, const SceneMetrics& metrics);
void from_json(const nlohmann::json& json, SceneMetrics& metrics);

}  // namespace trav::scenarios
