#include "scenarios/run/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "common/statistics.h"
#include "mapping/traversability_mapper.h"

namespace trav::scenarios {
namespace {

// Mean and variance of absolute errors added one by one.
class ErrorAccumulator {
 public:
  void Add(double absolute_error) {
    sum_ += absolute_error;
    sum2_ += absolute_error * absolute_error;
    ++count_;
  }
  LayerError Result() const {
    LayerError error;
    error.known_cells = count_;
    if (count_ > 0) {
      error.mean = sum_ / count_;
      error.variance = std::max(0.0, sum2_ / count_ - error.mean * error.mean);
    }
    return error;
  }

 private:
  double sum_{0.0};
  double sum2_{0.0};
  int count_{0};
};

}  // namespace

LayerError CompareLayers(const Eigen::MatrixXf& predicted, const Eigen::MatrixXf& truth) {
  ErrorAccumulator error;
  for (Eigen::Index i = 0; i < predicted.size(); ++i) {
    if (std::isnan(predicted.data()[i]) || std::isnan(truth.data()[i])) continue;
    error.Add(std::abs(predicted.data()[i] - truth.data()[i]));
  }
  return error.Result();
}

LayerError CompareWithTruth(const common::GridLayers& map, const common::GridLayers& truth_W,
                            const std::string& layer) {
  const common::GridGeometry& g = map.geometry();
  const Eigen::MatrixXf& predicted = map.Layer(layer);
  const Eigen::MatrixXf& truth_layer = truth_W.Layer(layer);
  Eigen::MatrixXf truth = Eigen::MatrixXf::Constant(g.num_x, g.num_y, NAN);
  for (int iy = 0; iy < g.num_y; ++iy) {
    for (int ix = 0; ix < g.num_x; ++ix) {
      if (std::isnan(predicted(ix, iy))) continue;
      const std::optional<Eigen::Vector2i> cell =
          truth_W.geometry().CellIndex(g.CellCenter(ix, iy));
      if (cell) truth(ix, iy) = truth_layer(cell->x(), cell->y());
    }
  }
  return CompareLayers(predicted, truth);
}

ObservedCells::ObservedCells(const common::GridGeometry& geometry, const mapping::MapArea& area)
    : geometry_(geometry),
      area_(area),
      observed_(static_cast<std::size_t>(geometry.num_x) * geometry.num_y, false) {}

int ObservedCells::Add(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB) {
  mapping::MapUpdateResult counts;
  crop_.Crop(points_W, p_WB, area_.window_m, area_.max_height_above_robot_m,
             std::numeric_limits<double>::infinity(), &counts);
  const auto window = crop_.window();
  int added = 0;
  for (Eigen::Index i = 0; i < window.cols(); ++i) {
    const std::optional<Eigen::Vector2i> cell =
        geometry_.CellIndex(window.col(i).head<2>().cast<double>());
    if (!cell) continue;
    const std::size_t index = static_cast<std::size_t>(cell->x() + cell->y() * geometry_.num_x);
    if (observed_[index]) continue;
    observed_[index] = true;
    cells_.push_back(*cell);
    ++added;
  }
  return added;
}

std::vector<int> MapCellIndices(const common::GridGeometry& geometry, const ObservedCells& observed,
                                std::size_t cells) {
  const std::vector<Eigen::Vector2i>& observed_cells = observed.cells();
  std::vector<int> indices(std::min(cells, observed_cells.size()), -1);
  for (std::size_t i = 0; i < indices.size(); ++i) {
    const Eigen::Vector2i& cell = observed_cells[i];
    const std::optional<Eigen::Vector2i> in_map =
        geometry.CellIndex(observed.geometry().CellCenter(cell.x(), cell.y()));
    if (in_map) indices[i] = in_map->x() + in_map->y() * geometry.num_x;
  }
  return indices;
}

LayerError CompareObserved(const Eigen::MatrixXf& map_layer, const Eigen::MatrixXf& truth_layer,
                           const ObservedCells& observed, const std::vector<int>& map_cells) {
  ErrorAccumulator error;
  const std::vector<Eigen::Vector2i>& observed_cells = observed.cells();
  for (std::size_t i = 0; i < map_cells.size(); ++i) {
    const Eigen::Vector2i& cell = observed_cells[i];
    const float expected = truth_layer(cell.x(), cell.y());
    if (std::isnan(expected) || map_cells[i] < 0) continue;
    const float predicted = map_layer.data()[map_cells[i]];
    if (!std::isnan(predicted)) error.Add(std::abs(static_cast<double>(predicted) - expected));
  }
  return error.Result();
}

LayerError CompareObserved(const common::GridLayers& map, const common::GridLayers& truth_W,
                           const ObservedCells& observed, const std::string& layer,
                           std::size_t cells) {
  return CompareObserved(map.Layer(layer), truth_W.Layer(layer), observed,
                         MapCellIndices(map.geometry(), observed, cells));
}

namespace {

int CostBin(double value) {
  return std::clamp(static_cast<int>(std::lround(value * kCostSteps)), 0, kCostSteps);
}

std::optional<double> Defined(double value) {
  return std::isnan(value) ? std::nullopt : std::optional<double>(value);
}

}  // namespace

nlohmann::json NumberOrNull(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

std::optional<double> OptionalNumber(const nlohmann::json& json) {
  return json.is_null() ? std::nullopt : std::optional<double>(json.get<double>());
}

void to_json(nlohmann::json& json, const HazardScores& s) {
  json = {{"auroc", NumberOrNull(s.auroc)},
          {"average_precision", NumberOrNull(s.average_precision)},
          {"spearman", NumberOrNull(s.spearman)},
          {"elevation_rmse", NumberOrNull(s.elevation_rmse_m)},
          {"hazard_cells", s.hazard_cells},
          {"compared_cells", s.compared_cells},
          {"cost_truth_histogram", s.cost_truth_histogram}};
}

void from_json(const nlohmann::json& json, HazardScores& s) {
  s.auroc = OptionalNumber(json.at("auroc"));
  s.average_precision = OptionalNumber(json.at("average_precision"));
  s.spearman = OptionalNumber(json.at("spearman"));
  s.elevation_rmse_m = OptionalNumber(json.at("elevation_rmse"));
  json.at("hazard_cells").get_to(s.hazard_cells);
  json.at("compared_cells").get_to(s.compared_cells);
  json.at("cost_truth_histogram").get_to(s.cost_truth_histogram);
}

HazardScores ScoreHazards(const common::GridLayers& map, const common::GridLayers& truth_W,
                          const ObservedCells& observed, double lethal_threshold) {
  const std::string& cost_layer = mapping::layers::kTraversability;
  const std::string& elevation_layer = mapping::layers::kElevation;
  const Eigen::MatrixXf& truth_cost = truth_W.Layer(cost_layer);
  const Eigen::MatrixXf& map_cost = map.Layer(cost_layer);
  const bool elevations = map.Has(elevation_layer) && truth_W.Has(elevation_layer);
  const Eigen::MatrixXf* truth_elevation = elevations ? &truth_W.Layer(elevation_layer) : nullptr;
  const Eigen::MatrixXf* map_elevation = elevations ? &map.Layer(elevation_layer) : nullptr;
  std::vector<double> cost, truth;
  std::vector<bool> hazard;
  std::map<std::pair<int, int>, int> histogram;
  double squared_height_error = 0.0;
  int heights = 0;
  for (const Eigen::Vector2i& cell : observed.cells()) {
    const Eigen::Vector2d centre_W = observed.geometry().CellCenter(cell.x(), cell.y());
    const float expected = truth_cost(cell.x(), cell.y());
    const std::optional<float> predicted = common::KnownValueAt(map.geometry(), map_cost, centre_W);
    if (!std::isnan(expected) && predicted) {
      cost.push_back(*predicted);
      truth.push_back(expected);
      hazard.push_back(expected >= lethal_threshold);
      ++histogram[{CostBin(*predicted), CostBin(expected)}];
    }
    if (!elevations) continue;
    const float ground = (*truth_elevation)(cell.x(), cell.y());
    const std::optional<float> height =
        common::KnownValueAt(map.geometry(), *map_elevation, centre_W);
    if (std::isnan(ground) || !height) continue;
    squared_height_error += (*height - ground) * (*height - ground);
    ++heights;
  }
  HazardScores scores;
  scores.compared_cells = static_cast<int>(cost.size());
  scores.hazard_cells = static_cast<int>(std::count(hazard.begin(), hazard.end(), true));
  scores.auroc = Defined(common::Auroc(cost, hazard));
  scores.average_precision = Defined(common::AveragePrecision(cost, hazard));
  scores.spearman = Defined(common::Spearman(cost, truth));
  if (heights > 0) scores.elevation_rmse_m = std::sqrt(squared_height_error / heights);
  for (const auto& [bins, count] : histogram) {
    scores.cost_truth_histogram.push_back({bins.first, bins.second, count});
  }
  return scores;
}

double BarnScore(bool success, double actual_time_s, double optimal_time_s) {
  if (!success || optimal_time_s <= 0.0) return 0.0;
  return optimal_time_s / std::clamp(actual_time_s, 2.0 * optimal_time_s, 8.0 * optimal_time_s);
}

bool ProgressMonitor::Update(double t_s, const Eigen::Vector2d& position_W) {
  if (!started_ || (position_W - anchor_W_).norm() > distance_m_) {
    anchor_W_ = position_W;
    anchor_time_s_ = t_s;
    started_ = true;
  }
  return t_s - anchor_time_s_ > window_s_;
}

LivelockMonitor::LivelockMonitor(double window_s, double radius_m)
    : window_s_(window_s), radius_m_(radius_m), sample_period_s_(window_s / 120.0) {}

bool LivelockMonitor::Update(double t_s, const Eigen::Vector2d& position_W,
                             const std::vector<Eigen::Vector2d>& movers_W) {
  if (window_s_ <= 0.0) return false;
  for (const Eigen::Vector2d& mover_W : movers_W) {
    if ((mover_W - position_W).norm() < kMoverDistance_m) {
      samples_.clear();
      return false;
    }
  }
  if (!samples_.empty() && t_s - samples_.back().t_s < sample_period_s_) return false;
  samples_.push_back({t_s, position_W});
  // keep the newest sample at least window_s old as the window's first
  while (samples_.size() > 1 && t_s - samples_[1].t_s >= window_s_) samples_.pop_front();
  if (t_s - samples_.front().t_s < window_s_) return false;
  Eigen::Vector2d mean_W = Eigen::Vector2d::Zero();
  for (const Sample& sample : samples_) mean_W += sample.position_W;
  mean_W /= static_cast<double>(samples_.size());
  for (const Sample& sample : samples_) {
    if ((sample.position_W - mean_W).norm() > radius_m_) return false;
  }
  return true;
}

double ModuleTimes::Total(const std::string& module) const {
  const auto it = totals_ms_.find(module);
  return it == totals_ms_.end() ? 0.0 : it->second;
}

RelativePoseError RelativePoseErrorOver(const std::vector<PoseSample>& samples, double stretch_m) {
  RelativePoseError error;
  std::size_t j = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    j = std::max(j, i);
    while (j < samples.size() && samples[j].distance_m - samples[i].distance_m < stretch_m) ++j;
    if (j == samples.size()) break;
    const Eigen::Isometry3d true_motion = samples[i].X_WB.inverse() * samples[j].X_WB;
    const Eigen::Isometry3d estimated_motion = samples[i].X_OB.inverse() * samples[j].X_OB;
    const Eigen::Isometry3d difference = true_motion.inverse() * estimated_motion;
    error.translation_m += difference.translation().norm();
    error.yaw_deg += std::abs(std::atan2(difference.linear()(1, 0), difference.linear()(0, 0)));
    ++error.stretches;
  }
  if (error.stretches > 0) {
    error.translation_m /= error.stretches;
    error.yaw_deg *= 180.0 / M_PI / error.stretches;
  }
  return error;
}

std::map<std::string, ModuleTime> ModuleTimes::Summary() const {
  std::map<std::string, ModuleTime> times;
  for (const auto& [module, samples] : samples_) {
    std::vector<double> sorted = samples;
    std::sort(sorted.begin(), sorted.end());
    times[module] = {static_cast<int>(sorted.size()),
                     sorted.empty() ? 0.0 : sorted[sorted.size() / 2],
                     sorted.empty() ? 0.0 : sorted.back(), Total(module) / 1e3};
  }
  return times;
}

void to_json(nlohmann::json& json, const ModuleTime& time) {
  json = {{"calls", time.calls},
          {"median_ms", time.median_ms},
          {"max_ms", time.max_ms},
          {"total_s", time.total_s}};
}

}  // namespace trav::scenarios
