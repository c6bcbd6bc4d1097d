#include "scenarios/experiments/eval_metrics.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <tuple>

#include <nlohmann/json.hpp>

#include "common/statistics.h"

namespace trav::scenarios {
namespace {

constexpr int kBootstrapResamples = 2000;
constexpr std::uint64_t kBootstrapSeed = 1;
// A bootstrap over fewer scenes only resamples their few values: no claim is made from it.
constexpr int kMinimumScenesForAClaim = 5;

}  // namespace

std::optional<double> MetricOf(const SceneMetrics& m, const std::string& name) {
  if (name == "mean_error") return m.mean_error;
  if (name == "auroc") return m.auroc;
  if (name == "average_precision") return m.average_precision;
  if (name == "spearman") return m.spearman;
  if (name == "calibrated_mae") return m.calibrated_mae;
  if (name == "elevation_rmse") return m.elevation_rmse;
  return std::nullopt;
}

void AddCells(const HazardScores& scene, int sign, CostTruthSums* sums) {
  for (const std::array<int, 3>& entry : scene.cost_truth_histogram) {
    std::pair<long long, long long>& bin = (*sums)[entry[0]];
    bin.first += sign * static_cast<long long>(entry[1]) * entry[2];
    bin.second += sign * static_cast<long long>(entry[2]);
  }
}

std::optional<double> CalibratedMae(const HazardScores& scene, const CostTruthSums& others) {
  // the fit: per cost bin of the other scenes' cells, their mean truth weighted by their count
  std::vector<double> x, y, weights;
  for (const auto& [bin, sums] : others) {
    if (sums.second <= 0) continue;
    x.push_back(static_cast<double>(bin) / kCostSteps);
    y.push_back(static_cast<double>(sums.first) / static_cast<double>(sums.second) / kCostSteps);
    weights.push_back(static_cast<double>(sums.second));
  }
  if (x.empty() || scene.cost_truth_histogram.empty()) return std::nullopt;
  const common::IsotonicFit calibration(x, y, weights);
  double error = 0.0, cells = 0.0;
  for (const std::array<int, 3>& entry : scene.cost_truth_histogram) {
    const double calibrated = calibration(static_cast<double>(entry[0]) / kCostSteps);
    error += entry[2] * std::abs(calibrated - static_cast<double>(entry[1]) / kCostSteps);
    cells += entry[2];
  }
  return error / cells;
}

std::vector<SceneMetrics> MethodSceneMetrics(const std::vector<EvalSceneRecord>& scenes,
                                             const std::string& method) {
  std::vector<const EvalSceneRecord*> with_method;
  for (const EvalSceneRecord& scene : scenes) {
    if (scene.methods.count(method) > 0) with_method.push_back(&scene);
  }
  // every scene's cells once; each scene's fit takes its own back out
  CostTruthSums all;
  for (const EvalSceneRecord* scene : with_method)
    AddCells(scene->methods.at(method).hazards, 1, &all);
  std::vector<SceneMetrics> metrics;
  for (const EvalSceneRecord* scene : with_method) {
    const EvalMethodRecord& record = scene->methods.at(method);
    CostTruthSums others = all;
    AddCells(record.hazards, -1, &others);
    SceneMetrics m;
    m.id = scene->id;
    m.mean_error = record.mean_error;
    m.auroc = record.hazards.auroc;
    m.average_precision = record.hazards.average_precision;
    m.spearman = record.hazards.spearman;
    m.calibrated_mae = CalibratedMae(record.hazards, others);
    m.elevation_rmse = record.hazards.elevation_rmse_m;
    metrics.push_back(m);
  }
  return metrics;
}

std::vector<PairedDifference> PairedDifferences(const std::vector<SceneMetrics>& method,
                                                const std::vector<SceneMetrics>& reference) {
  std::vector<PairedDifference> differences;
  for (const MetricName& metric : kComparedMetrics) {
    std::vector<double> values;
    for (const SceneMetrics& m : method) {
      for (const SceneMetrics& r : reference) {
        if (m.id != r.id) continue;
        const std::optional<double> a = MetricOf(m, metric.name), b = MetricOf(r, metric.name);
        if (a && b) values.push_back(*a - *b);
      }
    }
    if (values.empty()) continue;
    PairedDifference d;
    d.metric = metric.name;
    d.scenes = static_cast<int>(values.size());
    for (const double v : values) d.mean += v / static_cast<double>(values.size());
    std::tie(d.low, d.high) =
        common::BootstrapMeanInterval(values, 0.95, kBootstrapResamples, kBootstrapSeed);
    const bool enough = d.scenes >= kMinimumScenesForAClaim;
    const bool above = enough && d.low > 0.0, below = enough && d.high < 0.0;
    d.verdict = !(above || below)                    ? "not settled"
                : (above == metric.higher_is_better) ? "better"
                                                     : "worse";
    differences.push_back(d);
  }
  return differences;
}

void to_json(nlohmann::json& json, const PairedDifference& d) {
  json = {{"metric", d.metric}, {"scenes", d.scenes}, {"mean_difference", d.mean},
          {"low", d.low},       {"high", d.high},     {"verdict", d.verdict}};
}

void from_json(const nlohmann::json& json, PairedDifference& d) {
  json.at("metric").get_to(d.metric);
  json.at("scenes").get_to(d.scenes);
  json.at("mean_difference").get_to(d.mean);
  json.at("low").get_to(d.low);
  json.at("high").get_to(d.high);
  json.at("verdict").get_to(d.verdict);
}

void to_json(nlohmann::json& json, const SceneMetrics& m) {
  json = {{"scene", m.id},
          {"mean_error", NumberOrNull(m.mean_error)},
          {"auroc", NumberOrNull(m.auroc)},
          {"average_precision", NumberOrNull(m.average_precision)},
          {"spearman", NumberOrNull(m.spearman)},
          {"calibrated_mae", NumberOrNull(m.calibrated_mae)},
          {"elevation_rmse", NumberOrNull(m.elevation_rmse)}};
}

void from_json(const nlohmann::json& json, SceneMetrics& m) {
  json.at("scene").get_to(m.id);
  m.mean_error = OptionalNumber(json.at("mean_error"));
  m.auroc = OptionalNumber(json.at("auroc"));
  m.average_precision = OptionalNumber(json.at("average_precision"));
  m.spearman = OptionalNumber(json.at("spearman"));
  m.calibrated_mae = OptionalNumber(json.at("calibrated_mae"));
  m.elevation_rmse = OptionalNumber(json.at("elevation_rmse"));
}

}  // namespace trav::scenarios
