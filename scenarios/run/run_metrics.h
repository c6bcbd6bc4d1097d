#pragma once

#include <array>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json_fwd.hpp>

#include "common/grid.h"
#include "common/point_cloud.h"
#include "mapping/fsgp_config.h"
#include "mapping/window.h"

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

/// The cells of a world grid that LiDAR points have fallen in so far, in the order first observed:
/// the cells over which `trav eval` scores a map (the paper scores observed cells only, so
/// occlusion gaps that a regression fills in do not count). A point counts where the mappers take
/// it: in the square window around the base, no higher than the height limit above it.
class ObservedCells {
 public:
  /// `geometry`: the grid of the ground truth; `area`: the mappers' window and height limit.
  ObservedCells(const common::GridGeometry& geometry, const mapping::MapArea& area);

  /// Adds the cells of one frame's points (W), taken with the base at p_WB; returns how many
  /// cells are new.
  int Add(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB);

  /// The observed cells (ix, iy) of the grid, in the order first observed.
  const std::vector<Eigen::Vector2i>& cells() const { return cells_; }
  const common::GridGeometry& geometry() const { return geometry_; }

 private:
  common::GridGeometry geometry_;
  mapping::MapArea area_;
  std::vector<bool> observed_;  // per cell, ix + iy * num_x
  std::vector<Eigen::Vector2i> cells_;
  mapping::WindowCrop crop_;
};

/// `map`'s `layer` against the ground truth `truth_W` (on `observed`'s grid) over the first
/// `cells` observed cells (all by default; the cells are in the order first observed, so those of
/// the frames up to one are the first ones): each whose centre lies in a known cell of the map
/// counts once.
LayerError CompareObserved(const common::GridLayers& map, const common::GridLayers& truth_W,
                           const ObservedCells& observed, const std::string& layer,
                           std::size_t cells = std::numeric_limits<std::size_t>::max());

/// The index in a layer on `geometry` (ix + iy num_x, Eigen's column-major order) of the cell that
/// holds the centre of each of the first `cells` observed cells, -1 where none: where
/// CompareObserved looks each up in a map on that geometry.
std::vector<int> MapCellIndices(const common::GridGeometry& geometry, const ObservedCells& observed,
                                std::size_t cells);

/// CompareObserved of a map's layer against the truth's on `observed`'s grid, over the observed
/// cells `map_cells` has (MapCellIndices of the map's geometry): for maps that share a geometry,
/// the cells looked up once.
LayerError CompareObserved(const Eigen::MatrixXf& map_layer, const Eigen::MatrixXf& truth_layer,
                           const ObservedCells& observed, const std::vector<int>& map_cells);

/// How well a map finds the hazards of the ground truth, over the observed cells whose cost it
/// knows (trav eval, docs/evaluation.md): the cost ranked against the truth's untraversable cells
/// (truth cost >= `lethal_threshold`), rank correlation with the truth's cost, and the elevation
/// error against the dense ground; unset where undefined (no hazard, no free cell, no spread, no
/// elevation layer).
struct HazardScores {
  int compared_cells{0};
  int hazard_cells{0};
  std::optional<double> auroc;
  std::optional<double> average_precision;
  std::optional<double> spearman;
  std::optional<double> elevation_rmse_m;
  /// Cells counted by cost and truth rounded to 1 / kCostSteps (bin k: value k / kCostSteps), as
  /// {cost bin, truth bin, count} in bin order: what calibrating the cost on other scenes needs.
  std::vector<std::array<int, 3>> cost_truth_histogram;
};

/// Steps of HazardScores::cost_truth_histogram over [0, 1] on each axis (bins 0 to kCostSteps).
inline constexpr int kCostSteps = 100;

/// A number, or JSON null when unset; and back.
nlohmann::json NumberOrNull(const std::optional<double>& value);
std::optional<double> OptionalNumber(const nlohmann::json& json);

/// The scores as JSON fields (auroc, average_precision, spearman, elevation_rmse: a number or
/// null; hazard_cells, compared_cells, cost_truth_histogram), and back.
void to_json(nlohmann::json& json, const HazardScores& scores);
void from_json(const nlohmann::json& json, HazardScores& scores);

HazardScores ScoreHazards(const common::GridLayers& map, const common::GridLayers& truth_W,
                          const ObservedCells& observed, double lethal_threshold);

/// BARN Challenge score (since 2024): 1_success * OT / clip(AT, 2 OT, 8 OT), in [0, 0.5]; OT the
/// optimal time, AT the actual time [s]. 0 if OT is not positive.
double BarnScore(bool success, double actual_time_s, double optimal_time_s);

/// Detects a robot that no longer moves: stuck when it has stayed within `distance_m` of one place
/// for `window_s` seconds (wedged, high-centred, or waiting for a plan that never comes). A robot
/// that wanders without reaching its goal is a timeout, not stuck.
class ProgressMonitor {
 public:
  ProgressMonitor(double window_s, double distance_m)
      : window_s_(window_s), distance_m_(distance_m) {}

  /// Records the position at time t; true if stuck.
  bool Update(double t_s, const Eigen::Vector2d& position_W);

 private:
  double window_s_;
  double distance_m_;
  Eigen::Vector2d anchor_W_{Eigen::Vector2d::Zero()};
  double anchor_time_s_{0.0};
  bool started_{false};
};

/// Detects a robot that moves but gets nowhere: back and forth between plans and freeing
/// manoeuvres (a back-out, a turn, the plan again) round one spot, which ProgressMonitor does not
/// see because each move leaves its small disc, and which keeps the navigator's no-plan patience
/// from running because plans are found. Livelocked when, over the last `window_s` seconds, every
/// position (sampled every window_s / 120) lay within `radius_m` of the positions' mean; a
/// detour, however long, moves the mean away and never fires. Time with a mover within
/// kMoverDistance_m of the robot does not count (the window starts again): waiting for traffic
/// and giving way to it, back and forth, is not a livelock. `window_s` 0 turns it off.
class LivelockMonitor {
 public:
  static constexpr double kMoverDistance_m = 3.0;

  LivelockMonitor(double window_s, double radius_m);

  /// Records the position at time t with the movers' positions then; true if livelocked.
  bool Update(double t_s, const Eigen::Vector2d& position_W,
              const std::vector<Eigen::Vector2d>& movers_W = {});

 private:
  struct Sample {
    double t_s;
    Eigen::Vector2d position_W;
  };
  double window_s_;
  double radius_m_;
  double sample_period_s_;
  std::deque<Sample> samples_;
};

/// The modules timed per run (ModuleTimes), as named in summary.json's "compute" and
/// timeseries.csv.
inline constexpr const char* kTimedModules[] = {"lidar",   "mapping", "planning",
                                                "control", "physics", "render"};

/// The robot's pose at a distance driven: the true one and the estimate the stack used.
struct PoseSample {
  double distance_m{0.0};
  Eigen::Isometry3d X_WB{Eigen::Isometry3d::Identity()};
  Eigen::Isometry3d X_OB{Eigen::Isometry3d::Identity()};
};

/// The relative pose error of an estimate at one stretch length, odometry's usual drift metric
/// (KITTI's, at one length): for every sample i and the first sample j at least `stretch_m`
/// farther along, the difference between the estimated motion X_OB(i)^-1 X_OB(j) and the true one;
/// the means of its translation [m] and of its yaw [deg], over `stretches` pairs (0, and means 0,
/// when the samples span less than `stretch_m`).
struct RelativePoseError {
  double translation_m{0.0};
  double yaw_deg{0.0};
  int stretches{0};
};
RelativePoseError RelativePoseErrorOver(const std::vector<PoseSample>& samples, double stretch_m);

/// One module's wall time over a run: summary.json's compute.<module>.
struct ModuleTime {
  int calls{0};
  double median_ms{0.0};  ///< per call
  double max_ms{0.0};     ///< per call
  double total_s{0.0};
};

/// summary.json's compute.<module> object: calls, median_ms, max_ms, total_s.
void to_json(nlohmann::json& json, const ModuleTime& time);

/// Wall time per module and per call [ms], for the summary's median and maximum.
class ModuleTimes {
 public:
  void Add(const std::string& module, double ms) {
    samples_[module].push_back(ms);
    totals_ms_[module] += ms;
  }

  /// Total time of a module so far [ms].
  double Total(const std::string& module) const;

  /// The time of every module timed so far, by name.
  std::map<std::string, ModuleTime> Summary() const;

 private:
  std::map<std::string, std::vector<double>> samples_;
  std::map<std::string, double> totals_ms_;
};

}  // namespace trav::scenarios
