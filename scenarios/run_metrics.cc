#include "scenarios/run_metrics.h"

#include <algorithm>
#include <cmath>

namespace trav::scenarios {

LayerError CompareLayers(const Eigen::MatrixXf& predicted, const Eigen::MatrixXf& truth) {
  LayerError error;
  double sum = 0.0, sum2 = 0.0;
  for (Eigen::Index i = 0; i < predicted.size(); ++i) {
    if (std::isnan(predicted.data()[i]) || std::isnan(truth.data()[i])) continue;
    const double e = std::abs(predicted.data()[i] - truth.data()[i]);
    sum += e;
    sum2 += e * e;
    ++error.known_cells;
  }
  if (error.known_cells > 0) {
    error.mean = sum / error.known_cells;
    error.variance = std::max(0.0, sum2 / error.known_cells - error.mean * error.mean);
  }
  return error;
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

nlohmann::json ModuleTimes::ToJson() const {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& [module, samples] : samples_) {
    std::vector<double> sorted = samples;
    std::sort(sorted.begin(), sorted.end());
    json[module] = {{"calls", sorted.size()},
                    {"median_ms", sorted.empty() ? 0.0 : sorted[sorted.size() / 2]},
                    {"max_ms", sorted.empty() ? 0.0 : sorted.back()},
                    {"total_s", Total(module) / 1e3}};
  }
  return json;
}

}  // namespace trav::scenarios
