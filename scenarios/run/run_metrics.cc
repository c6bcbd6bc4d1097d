#include "scenarios/run/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <nlohmann/json.hpp>

#include "mapping/window.h"

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
  const Eigen::Matrix3Xf window =
      mapping::CropWindow(points_W, p_WB, area_.window_m, area_.max_height_above_robot_m, &counts);
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

LayerError CompareObserved(const common::GridLayers& map, const common::GridLayers& truth_W,
                           const ObservedCells& observed, const std::string& layer) {
  const Eigen::MatrixXf& truth = truth_W.Layer(layer);
  ErrorAccumulator error;
  for (const Eigen::Vector2i& cell : observed.cells()) {
    const float expected = truth(cell.x(), cell.y());
    if (std::isnan(expected)) continue;
    const std::optional<float> predicted =
        map.At(layer, observed.geometry().CellCenter(cell.x(), cell.y()));
    if (predicted) error.Add(std::abs(static_cast<double>(*predicted) - expected));
  }
  return error.Result();
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

double ModuleTimes::Total(const std::string& module) const {
  const auto it = totals_ms_.find(module);
  return it == totals_ms_.end() ? 0.0 : it->second;
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
