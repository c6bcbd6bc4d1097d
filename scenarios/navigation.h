#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/grid.h"
#include "common/pose.h"
#include "common/random.h"
#include "common/trajectory.h"
#include "controller/mpc.h"
#include "planner/navigation_planner.h"
#include "scenarios/tracking.h"

namespace trav::scenarios {

/// Settings of the autonomy loop (scenario key `navigation`).
struct NavigationSettings {
  double goal_radius_m{0.5};       ///< success when the base is this close to the goal [m]
  double planning_rate_hz{5.0};    ///< periodic replanning [Hz], in (0, 50]
  double replan_deviation_m{0.5};  ///< replan when the robot strays this far from the plan [m]
  double safety_horizon_s{1.5};    ///< look-ahead of the per-tick safety check [s]
  double stuck_time_s{10.0};       ///< stuck: within `stuck_distance_m` of one place this long [s]
  double stuck_distance_m{0.3};    ///< [m]
  double planning_failure_time_s{5.0};  ///< no valid plan for this long is a planning failure [s]
  double near_miss_clearance_m{0.3};    ///< a mover closer than this is a near miss [m], >= 0
  /// The planner knows every mover's true position and velocity; else it gets the movers it
  /// perceives in the scans within `mover_sensing_range_m` (mapping::MoverTracker).
  bool movers_from_ground_truth{true};
  double mover_sensing_range_m{15.0};  ///< [m], > 0
  /// Localisation: the navigator sees the true pose plus white noise (standard deviations) and a
  /// drift (a random walk of the position offset, growing by `drift_m_per_sqrt_s` per sqrt(s)),
  /// drawn from `localization_seed`. Zero: ground truth.
  double position_noise_m{0.0};
  double yaw_noise_rad{0.0};
  double drift_m_per_sqrt_s{0.0};
  std::uint64_t localization_seed{1};
  /// The map reaches the planner this long after the frame it comes from [s], >= 0.
  double mapping_latency_s{0.0};
};

/// The pose the navigator believes: the true one with the settings' noise and drift. Seeded and
/// repeatable; with zero noise and drift it returns the true state unchanged.
class Localization {
 public:
  explicit Localization(const NavigationSettings& settings);

  /// The estimate of `truth` (the state at its time; call once per control step, in time order).
  common::RobotState Estimate(const common::RobotState& truth);

  /// The current drift offset [m].
  const Eigen::Vector2d& drift_W() const { return drift_W_; }

 private:
  NavigationSettings settings_;
  common::Random random_;
  Eigen::Vector2d drift_W_{Eigen::Vector2d::Zero()};
  double last_time_s_{0.0};
};

/// Checks settings. @throws common::InputError naming `navigation.<key>` and the value.
void ValidateNavigationSettings(const NavigationSettings& settings);

/// Why the navigator replanned.
enum class ReplanReason {
  kNone,
  kFirst,
  kPeriodic,
  kNewLethalCells,
  kDeviation,
  kSafetyStop,
  kStalled,  ///< the plan says move, the robot has not for a second
};

/// The autonomy stack of one robot: plans on the latest traversability map at a fixed rate and on
/// events (the plan crosses newly lethal cells, the robot strays from it, a safety stop), tracks
/// the plan with the MPC at the control rate, and brakes when the plan ahead becomes unsafe (it
/// enters lethal cells, or comes within the robot's radius of a predicted mover) or when there is
/// no valid plan. Time is simulation time; planning is synchronous (the world waits for it).
class Navigator {
 public:
  /// @throws common::InputError for invalid planner or MPC settings.
  Navigator(const NavigationSettings& settings, const planner::NavigationPlannerConfig& planner,
            const controller::MpcConfig& mpc, const Eigen::Vector2d& goal_W);

  /// The body twist command at the state's time. `map` is the latest traversability map (null
  /// before the first one: the robot waits); `map_updated` says it changed since the last call;
  /// `movers` are the predicted moving obstacles.
  common::Twist2 Update(const common::RobotState& state, const common::GridLayers* map,
                        bool map_updated, const std::vector<planner::MovingObstacle>& movers);

  /// Time since the last valid plan, or since the start if there was none [s]. A plan toward the
  /// substitute of an unreachable goal that ends within the goal radius of the robot is not valid:
  /// the goal cannot be reached from here.
  double time_without_plan_s(double now_s) const;

  /// The trajectory being tracked (empty before the first plan).
  const common::Trajectory& trajectory() const { return trajectory_; }

  /// The latest plan's waypoints (A* simplified) [m].
  const std::vector<Eigen::Vector2d>& waypoints_W() const { return waypoints_W_; }

  /// Counters and timings for the summary.
  struct Statistics {
    int plans{0};                     ///< planning calls
    int failed_plans{0};              ///< calls without a usable trajectory
    int safety_stops{0};              ///< control ticks that braked for safety
    int replans_on_events{0};         ///< calls triggered by an event rather than the clock
    std::vector<double> planning_ms;  ///< wall time of each planning call
    std::vector<double> control_ms;   ///< wall time of each MPC solve
    std::string last_status;          ///< planner status of the latest call
  };
  const Statistics& statistics() const { return statistics_; }

  /// Tracking metrics against the trajectories followed.
  TrackingMetrics tracking_metrics() const { return tracker_.Metrics(); }

 private:
  ReplanReason ReasonToReplan(const common::RobotState& state, const common::GridLayers* map,
                              bool map_updated);
  void Replan(const common::RobotState& state, const common::GridLayers& map,
              const std::vector<planner::MovingObstacle>& movers, ReplanReason reason);
  bool AheadIsSafe(double now_s, const common::GridLayers* map,
                   const std::vector<planner::MovingObstacle>& movers) const;

  NavigationSettings settings_;
  planner::NavigationPlanner planner_;
  MpcTracker tracker_;
  Eigen::Vector2d goal_W_;
  common::Trajectory trajectory_;
  std::vector<Eigen::Vector2d> waypoints_W_;
  double next_plan_s_{0.0};
  double last_valid_plan_s_{0.0};
  bool force_replan_{false};
  bool map_check_pending_{false};  // a map update not yet checked against the plan
  double last_moving_s_{0.0};      // last time the robot moved or was meant to stand still
  Statistics statistics_;
};

}  // namespace trav::scenarios
