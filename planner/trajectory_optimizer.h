#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/archive.h"
#include "common/enum_names.h"
#include "common/footprint.h"
#include "common/trajectory.h"
#include "planner/cost_field.h"
#include "planner/trajectory_cost.h"

namespace trav::planner {

/// Settings of the trajectory optimiser (scenario key `planner.optimizer`).
struct TrajectoryOptimizerConfig {
  DynamicLimits limits;
  TrajectoryCostWeights weights;
  /// The robot's outline: every point of its boundary keeps the clearance (the closed loop sets
  /// it from the robot file; NavigationPlannerConfig::footprint).
  common::Footprint footprint;
  /// Gap kept between the footprint and lethal cells [m], >= 0; shrinks to 85 % of the start's or
  /// goal's gap when that is less (DDR-opt), so that an end near lethal cells is not infeasible by
  /// itself, and below zero for a start that overlaps a lethal cell (its gap less 15 % of its
  /// size). The default is the tracker's margin at speed where the map bounds a face within its
  /// cell (docs/navigation.md, "One robot model for clearance").
  double clearance_m{0.15};
  /// When no trajectory keeps `clearance_m`, one more cold solve keeps this instead [m], in
  /// [0, clearance]; the search admits exactly the cells where the footprint's inscribed disc keeps
  /// it (NavigationPlannerConfig::SearchConfig).
  double min_clearance_m{0.01};
  double robot_radius_m{0.35};        ///< disc around the base for moving obstacles [m], > 0
  double obstacle_clearance_m{0.3};   ///< gap kept between the robot's and a mover's disc [m], >= 0
  double clearance_growth_m_s{0.05};  ///< growth of that gap per second ahead [m/s], >= 0
  double piece_length_m{1.0};         ///< arc length per polynomial piece in the initial guess, > 0
  int samples_per_piece{8};           ///< integration intervals per piece, even, in [2, 64]
  double initial_speed_fraction{0.6};  ///< initial guess cruises at this fraction of the limits
  double terminal_tolerance_m{0.05};   ///< end-position error accepted as converged [m], > 0
  double violation_tolerance{0.05};    ///< largest relative constraint violation accepted, >= 0
  int max_iterations{400};             ///< L-BFGS iterations over all augmented-Lagrangian rounds
  int max_rounds{6};                   ///< augmented-Lagrangian rounds, >= 1
  double initial_penalty{1.0e3};       ///< rho of the first round
  double penalty_growth{10.0};         ///< rho is multiplied by this after each round, > 1
  double relative_cost_tolerance{1.0e-3};   ///< L-BFGS stops when the cost improves less [-]
  double output_step_s{0.02};               ///< sample spacing of the output trajectory [s], > 0
  bool warm_start{true};                    ///< start from the previous plan when it applies
  double warm_start_goal_tolerance_m{0.3};  ///< the previous plan applies to goals this close [m]

  /// The keys of scenario section `planner.optimizer` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("max_speed", &limits.max_speed_m_s, {0.01, 30});
    a->Field("max_yaw_rate", &limits.max_yaw_rate_rad_s, {0.01, 30});
    a->Field("max_acceleration", &limits.max_acceleration_m_s2, {0.01, 100});
    a->Field("max_yaw_acceleration", &limits.max_yaw_acceleration_rad_s2, {0.01, 100});
    a->Field("max_centripetal_acceleration", &limits.max_centripetal_acceleration_m_s2,
             {0.01, 100});
    a->Field("yaw_jerk_weight", &weights.yaw_jerk, {0, 1000000000.0});
    a->Field("arc_length_jerk_weight", &weights.arc_length_jerk, {0, 1000000000.0});
    a->Field("time_weight", &weights.time, {0, 1000000000.0});
    a->Field("traversability_weight", &weights.traversability, {0, 1000000000.0});
    a->Field("limits_weight", &weights.limits, {0, 1000000000.0});
    a->Field("clearance_weight", &weights.clearance, {0, 1000000000.0});
    a->Field("moving_obstacles_weight", &weights.moving_obstacles, {0, 1000000000.0});
    a->Field("clearance", &clearance_m, {0, 5});
    a->Field("min_clearance", &min_clearance_m, {0, 5});
    a->Field("robot_radius", &robot_radius_m, {0, 5});
    a->Field("obstacle_clearance", &obstacle_clearance_m, {0, 10});
    a->Field("clearance_growth", &clearance_growth_m_s, {0, 10});
    a->Field("piece_length", &piece_length_m, {0.1, 100});
    a->Field("samples_per_piece", &samples_per_piece, {1, 100});
    a->Field("max_iterations", &max_iterations, {1, 100000});
    a->Field("max_rounds", &max_rounds, {1, 100});
    a->Field("warm_start", &warm_start);
  }
};

/// Checks a config. @throws common::InputError naming the key (relative: "clearance").
void ValidateTrajectoryOptimizerConfig(const TrajectoryOptimizerConfig& config);

/// What to plan.
struct TrajectoryRequest {
  /// The robot's state: time, position, yaw, v, omega and forward acceleration.
  common::TrajectoryPoint start;
  Eigen::Vector2d goal_W{Eigen::Vector2d::Zero()};  ///< where to stop [m]
  /// A guide path from the start to the goal (e.g. simplified A* waypoints) [m]; empty: straight.
  std::vector<Eigen::Vector2d> guide_W;
  std::vector<MovingObstacle> obstacles;  ///< predicted movers
};

/// How an optimisation ended.
enum class OptimizationStatus {
  kConverged,       ///< at the goal within tolerance, every constraint within tolerance
  kIterationLimit,  ///< constraints within tolerance, but the end position not yet at the goal
  kInfeasible,      ///< a constraint violated beyond tolerance, or the goal far from reached
};

/// The names of OptimizationStatus's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<OptimizationStatus>, 3> kOptimizationStatusNames{
    {{OptimizationStatus::kConverged, "converged"},
     {OptimizationStatus::kIterationLimit, "iteration-limit"},
     {OptimizationStatus::kInfeasible, "infeasible"}}};
constexpr const auto& EnumNames(OptimizationStatus) { return kOptimizationStatusNames; }

/// What the solve did, for logs and summaries.
struct OptimizationDiagnostics {
  CostTerms costs;                 ///< each term at the solution (terminal: last round's)
  double max_violation{0.0};       ///< largest relative violation of a limit or clearance
  std::string worst_constraint;    ///< which constraint that was ("" if none)
  double clearance_m{0.0};         ///< clearance applied: the configured one, or less near the ends
  double min_clearance_m{0.0};     ///< smallest signed distance of the footprint to lethal cells
  double min_obstacle_gap_m{0.0};  ///< smallest gap between the robot's and a mover's disc
  double terminal_error_m{0.0};    ///< distance from the end position to the goal
  int iterations{0};               ///< L-BFGS iterations
  int evaluations{0};              ///< cost evaluations
  int rounds{0};                   ///< augmented-Lagrangian rounds
  int pieces{0};                   ///< polynomial pieces
  bool warm_started{false};
  double solve_time_s{0.0};  ///< wall time (not used by any decision)
};

/// An optimised trajectory.
struct OptimizedTrajectory {
  OptimizationStatus status{OptimizationStatus::kInfeasible};
  common::Trajectory trajectory;  ///< from the request's start time, sampled every output step
  OptimizationDiagnostics diagnostics;
};

/// DDR-opt style trajectory optimisation for the differential-drive (skid-steer) base on a
/// traversability map: minimum-jerk pieces in yaw and arc length (TrajectoryCost), dynamic limits,
/// clearance from lethal cells and from predicted moving obstacles, a traversability integral, time
/// regularisation, and the end position held by an augmented Lagrangian (PHR) around L-BFGS
/// (liblbfgs, backtracking Wolfe line search). The initial guess follows the request's guide path
/// at a fraction of the limits, straight along its segments and turning in place at its sharp
/// vertices; replanning toward the same goal starts from the previous plan shifted to the new start
/// time, and from the guide path again if that ends infeasible (the map changed). Deterministic:
/// the same calls in the same order give the same results (no decision depends on wall time).
/// Failure is a status, never an exception.
class TrajectoryOptimizer {
 public:
  /// @throws common::InputError for an invalid config.
  explicit TrajectoryOptimizer(const TrajectoryOptimizerConfig& config);

  /// Optimises a trajectory from `request.start` to `request.goal_W` on `field`.
  OptimizedTrajectory Optimize(const CostField& field, const TrajectoryRequest& request);

  /// Forgets the previous plan: the next call starts cold.
  void Reset() { previous_.reset(); }

  const TrajectoryOptimizerConfig& config() const { return config_; }

 private:
  // The solution of the last call, for warm starts.
  struct Solution {
    double start_time_s{0.0};
    Eigen::Vector2d goal_W{Eigen::Vector2d::Zero()};
    MinimumJerkPolynomial polynomial;
    Eigen::Vector2d lambda{Eigen::Vector2d::Zero()};
  };

  TrajectoryOptimizerConfig config_;
  std::optional<Solution> previous_;
};

}  // namespace trav::planner
