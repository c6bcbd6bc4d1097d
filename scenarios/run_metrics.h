#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "common/grid.h"

namespace trav::scenarios {

/// Mean and variance of |predicted - truth| over the cells known in both layers (same geometry).
struct LayerError {
  int known_cells{0};
  double mean{0.0};
  double variance{0.0};
};
LayerError CompareLayers(const Eigen::MatrixXf& predicted, const Eigen::MatrixXf& truth);

/// `map`'s traversability against the ground truth `truth_W` (a grid of the same resolution over
/// the world, cells aligned or not): each known cell of the map is compared with the truth at its
/// centre (nearest cell).
LayerError CompareWithTruth(const common::GridLayers& map, const common::GridLayers& truth_W,
                            const std::string& layer);

/// BARN Challenge score (since 2024): 1_success * OT / clip(AT, 2 OT, 8 OT), in [0, 0.5]; OT the
/// optimal time, AT the actual time [s]. 0 if OT is not positive.
double BarnScore(bool success, double actual_time_s, double optimal_time_s);

/// Detects a robot that makes no progress toward its goal: stuck when the best distance to the
/// goal has not improved by `distance_m` within the last `window_s` seconds.
class ProgressMonitor {
 public:
  ProgressMonitor(double window_s, double distance_m)
      : window_s_(window_s), distance_m_(distance_m) {}

  /// Records the distance to the goal at time t; true if stuck.
  bool Update(double t_s, double goal_distance_m);

 private:
  double window_s_;
  double distance_m_;
  double best_m_{1e300};
  double best_time_s_{0.0};
  bool started_{false};
};

/// Wall time per module and per call [ms], for the summary's median and maximum.
class ModuleTimes {
 public:
  void Add(const std::string& module, double ms) { samples_[module].push_back(ms); }

  /// Total time of a module so far [ms].
  double Total(const std::string& module) const;

  /// {module: {calls, median_ms, max_ms, total_s}}.
  nlohmann::json ToJson() const;

 private:
  std::map<std::string, std::vector<double>> samples_;
};

}  // namespace trav::scenarios
