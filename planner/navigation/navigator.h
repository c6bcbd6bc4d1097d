#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/archive.h"
#include "common/grid.h"
#include "common/pose.h"
#include "common/trajectory.h"
#include "controller/mpc_tracker.h"
#include "planner/navigation_planner.h"

namespace trav::planner {

/// Settings of the autonomy loop (scenario key `navigation`).
struct NavigationSettings {
  double goal_radius_m{0.5};       ///< success when the base is this close to the goal [m]
  double planning_rate_hz{5.0};    ///< periodic replanning [Hz], in (0, 50]
  double replan_deviation_m{0.5};  ///< replan when the robot strays this far from the plan [m]
  double safety_horizon_s{1.5};    ///< look-ahead of the per-tick safety check [s]
  double stuck_time_s{10.0};       ///< stuck: within `stuck_distance_m` of one place this long [s]
  double stuck_distance_m{0.3};    ///< [m]
  double planning_failure_time_s{5.0};  ///< no valid plan for this long is a planning failure [s]
  /// Plans, but no progress: a robot that has stayed within `livelock_radius_m` of one spot for
  /// this long (plans and freeing manoeuvres in a loop) is a planning failure [s]; 0 turns it off.
  double livelock_time_s{30.0};
  double livelock_radius_m{1.5};      ///< [m], > 0
  double near_miss_clearance_m{0.3};  ///< a mover closer than this is a near miss [m], >= 0

  /// The planner knows every mover's true position and velocity; else it gets the movers it
  /// perceives in the scans within `mover_sensing_range_m` (mapping::MoverTracker).
  bool movers_from_ground_truth{true};
  double mover_sensing_range_m{15.0};  ///< [m], > 0

  /// The map reaches the planner this long after the frame it comes from [s], >= 0.
  double mapping_latency_s{0.05};

  /// Climbing a step: when the robot, meant to drive on (the tracker asks for 0.3 m/s or more),
  /// has its nose up by at least `climb_pitch_deg` with a step of `climb_step_m` or more within
  /// the footprint's circumscribed radius (a cell whose roughness reads one:
  /// StepHeightOfRoughness), it drives straight at `climb_speed_m_s` (or the tracker's limit if
  /// lower) whatever the tracker asks, if that straight drive keeps the footprint clear of the
  /// map, until it has driven the footprint's length or the tracker stops or reverses; then no new
  /// climb until the nose has been down. A turn while the wheels climb stalls them at the face
  /// (docs/navigation.md, "Climbing a step"). 0 turns the hold off.
  double climb_speed_m_s{1.1};
  double climb_pitch_deg{10.0};  ///< (0, 90)
  double climb_step_m{0.08};     ///< [m], >= 0

  /// The keys of scenario section `navigation` that configure the loop (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("movers_from_ground_truth", &movers_from_ground_truth);
    a->Field("mover_sensing_range", &mover_sensing_range_m, {0, 500});
    a->Field("mapping_latency", &mapping_latency_s, {0, 10});
    a->Field("goal_radius", &goal_radius_m, {0.01, 100});
    a->Field("planning_rate", &planning_rate_hz, {0.1, 100});
    a->Field("replan_deviation", &replan_deviation_m, {0.01, 100});
    a->Field("safety_horizon", &safety_horizon_s, {0, 60});
    a->Field("stuck_time", &stuck_time_s, {0.1, 86400});
    a->Field("stuck_distance", &stuck_distance_m, {0, 100});
    a->Field("planning_failure_time", &planning_failure_time_s, {0.1, 86400});
    a->Field("livelock_time", &livelock_time_s, {0, 86400});
    a->Field("livelock_radius", &livelock_radius_m, {0.01, 100});
    a->Field("near_miss_clearance", &near_miss_clearance_m, {0, 10});
    a->Field("climb_speed", &climb_speed_m_s, {0, 30});
    a->Field("climb_pitch", &climb_pitch_deg, {0, 90});
    a->Field("climb_step", &climb_step_m, {0, 10});
  }
};

/// Checks settings. @throws common::InputError naming the key (relative: "goal_radius") and value.
void ValidateNavigationSettings(const NavigationSettings& settings);

/// Why the navigator replanned.
enum class ReplanReason {
  kNone,
  kFirst,
  kPeriodic,
  kNewLethalCells,
  kDeviation,
  kSafetyStop,
  kStalled,  ///< the plan says move, the robot has not for a second, and cannot back off
};

/// The names of ReplanReason's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<ReplanReason>, 7> kReplanReasonNames{{
    {ReplanReason::kNone, "none"},
    {ReplanReason::kFirst, "first"},
    {ReplanReason::kPeriodic, "periodic"},
    {ReplanReason::kNewLethalCells, "new-lethal-cells"},
    {ReplanReason::kDeviation, "deviation"},
    {ReplanReason::kSafetyStop, "safety-stop"},
    {ReplanReason::kStalled, "stalled"},
}};
constexpr const auto& EnumNames(ReplanReason) { return kReplanReasonNames; }

/// The MPC settings with which the navigator tracks its plans: the MPC never drives faster than the
/// planner's speed limit (a robot that fell behind a plan must not race to where the plan is now);
/// it may turn a little faster (20 %) to catch up a heading.
controller::MpcConfig PlanTrackingConfig(controller::MpcConfig mpc,
                                         const NavigationPlannerConfig& planner);

/// The speeds [m/s] of the drives that free a stopped or stalled robot, within the tracker's limits
/// (`tracking`, as PlanTrackingConfig gives them): giving way at a walker's pace (1 m/s) or the
/// tracker's limit that way if lower, backing off a stall at 0.6 m/s or the reverse limit if lower.
/// A speed of 0 means no such drive: a tracker that may not reverse (min_speed 0) gives way forward
/// only and never backs off.
struct FreeDriveSpeeds {
  double give_way_forward_m_s{0.0};   ///< giving way forward, >= 0
  double give_way_backward_m_s{0.0};  ///< giving way backward, >= 0
  double back_off_m_s{0.0};           ///< backing off a stall, >= 0
};
FreeDriveSpeeds FreeDriveSpeedsFor(const controller::MpcConfig& tracking);

/// What the navigator did in one control tick.
struct NavigatorTick {
  common::Twist2 command;                    ///< the body twist to apply
  ReplanReason replan{ReplanReason::kNone};  ///< why it planned (kNone: it did not plan)
  bool solved{false};                        ///< the MPC solved for a new command
  bool safety_stop{false};                   ///< it braked: the plan ahead is unsafe
  bool climbing{false};  ///< it held the climb command over a step (NavigationSettings)
};

/// The autonomy stack of one robot: plans on the latest traversability map at a fixed rate and on
/// events (the plan crosses newly lethal cells, the robot strays from it, a safety stop), tracks
/// the plan with the MPC at the control rate, and brakes when the plan ahead becomes unsafe (it
/// enters lethal cells, or comes within the robot's radius of a predicted mover) or when there is
/// no valid plan. A stopped robot that a predicted mover would reach gives way: it drives a short
/// straight stretch forward or backward, whichever keeps it furthest from the movers and clear
/// of the map, and replans after it; if a map update shows that drive no longer keeps clear, it
/// chooses again from where it is, or stops. A robot that stalls (the plan asks it to move, it
/// stays in place: a curb it cannot climb at that speed) backs off straight for a run-up, if that
/// keeps clear of the map, and replans after it. A robot climbing a step drives straight at the
/// climb speed for its length (docs/navigation.md). Time is simulation time;
/// planning is synchronous (the world waits for it).
class Navigator {
 public:
  /// @throws common::InputError for invalid planner or MPC settings.
  /// `search` finds the paths the trajectories follow (A* unless given); `tracker` tracks them
  /// (unless given, the MPC with `mpc` as PlanTrackingConfig limits it).
  Navigator(const NavigationSettings& settings, const NavigationPlannerConfig& planner,
            const controller::MpcConfig& mpc, const Eigen::Vector2d& goal_W,
            PathSearch search = AStarSearch,
            std::unique_ptr<controller::TrajectoryTracker> tracker = nullptr);

  /// The tick at the state's time: the body twist command and what was done for it. `map` is the
  /// latest traversability map (null before the first one: the robot waits); `map_updated` says it
  /// changed since the last call; `movers` are the predicted moving obstacles.
  NavigatorTick Update(const common::RobotState& state, const common::GridLayers* map,
                       bool map_updated, const std::vector<MovingObstacle>& movers);

  /// Time since the last valid plan, or since the start if there was none [s]. A plan toward the
  /// substitute of an unreachable goal that ends within the goal radius of the robot is not valid:
  /// the goal cannot be reached from here. A pose-search way counts as valid until the end of its
  /// narrows (NavigationPlan::commit_until_s), up to which it is followed without periodic replans,
  /// or until the robot gives way to a mover on it.
  double time_without_plan_s(double now_s) const;

  /// The planner's settings, with the footprint it plans for.
  const NavigationPlannerConfig& planner_config() const { return planner_.config(); }

  /// The trajectory being tracked (empty before the first plan).
  const common::Trajectory& trajectory() const { return trajectory_; }

  /// The tracker of the trajectory (its latest predicted horizon).
  const controller::TrajectoryTracker& tracker() const { return *tracker_; }

  /// The latest plan's waypoints (A* simplified) [m].
  const std::vector<Eigen::Vector2d>& waypoints_W() const { return waypoints_W_; }

  /// Counters and timings for the summary.
  struct Statistics {
    int plans{0};         ///< planning calls
    int failed_plans{0};  ///< calls without a usable trajectory
    /// Calls whose trajectory is a fallback, by Fallback (index kNone unused).
    std::array<int, kFallbackNames.size()> fallbacks{};
    int safety_stops{0};              ///< control ticks that braked for safety
    int give_ways{0};                 ///< times the stopped robot moved out of a mover's way
    int back_offs{0};                 ///< times the stalled robot backed off for a run-up
    int step_climbs{0};               ///< times the robot began to climb a step straight
    int replans_on_events{0};         ///< calls triggered by an event rather than the clock
    std::vector<double> planning_ms;  ///< wall time of each planning call
    std::vector<double> control_ms;   ///< wall time of each MPC solve
    std::string last_status;          ///< planner status of the latest call
  };
  const Statistics& statistics() const { return statistics_; }

  /// Tracking metrics against the trajectories followed.
  controller::TrackingMetrics tracking_metrics() const { return tracker_->Metrics(); }

 private:
  ReplanReason ReasonToReplan(const common::RobotState& state, const common::GridLayers* map,
                              bool map_updated);
  void Replan(const common::RobotState& state, const common::GridLayers& map,
              const std::vector<MovingObstacle>& movers, ReplanReason reason);
  bool AheadIsSafe(double now_s, const common::GridLayers* map,
                   const std::vector<MovingObstacle>& movers);
  // A short straight drive forward or backward that keeps the stopped robot furthest from the
  // movers closing in on it over the next seconds, if one keeps clear of the map and gains room.
  std::optional<common::Trajectory> GiveWay(const common::RobotState& state,
                                            const common::GridLayers& map,
                                            const std::vector<MovingObstacle>& movers);
  // True if the robot holds the climb command over a step of `map` while the tracker asks for
  // `command` (NavigationSettings::climb_speed_m_s); advances the climb's state.
  bool HoldsClimb(const common::RobotState& state, const common::GridLayers* map,
                  const common::Twist2& command);
  // The straight drive from the state's pose along its heading by length_m (backward if negative)
  // at speed_m_s, if the footprint keeps clear of `map` on it (KeepsClear).
  std::optional<common::Trajectory> StraightDrive(const common::RobotState& state,
                                                  const common::GridLayers& map, double length_m,
                                                  double speed_m_s);
  // True if a cell of `map` within reach_m of p_W reads a step of settings_.climb_step_m or more.
  bool StepWithinReach(const common::GridLayers& map, const Eigen::Vector2d& p_W,
                       double reach_m) const;
  // A straight drive backward along the heading of the stalled robot, the longest of
  // kBackOffDistances_m that keeps clear of the map, if one does.
  std::optional<common::Trajectory> BackOff(const common::RobotState& state,
                                            const common::GridLayers& map);
  // Starts following the freeing drive `drive` (give way, back off) at now_s: to its end, then
  // replan.
  void StartFreeDrive(common::Trajectory drive, double now_s);
  // The manoeuvre settings of the freeing drives: the planner's, at `speed_m_s` and the give-way
  // yaw rate.
  FallbackConfig FreeDriveConfig(double speed_m_s) const;
  // True if the footprint keeps min(optimizer.clearance, its gap at from_s) on `costs` along the
  // trajectory being followed from from_s to to_s (KeepsClear).
  bool WayKeepsClear(double from_s, double to_s, const CostMap& costs) const;
  // The costs of the map, built on first use after each map update.
  const CostMap& CostMapOf(const common::GridLayers& map);
  // The footprint's body points for clearance checks on `costs` (BodyPoints_B with the
  // optimiser's clearance).
  std::vector<Eigen::Vector2d> BodyPointsOn(const CostMap& costs) const;

  NavigationSettings settings_;
  NavigationPlanner planner_;
  std::unique_ptr<controller::TrajectoryTracker> tracker_;
  FreeDriveSpeeds free_drive_speeds_;
  double climb_speed_m_s_{0.0};  // settings_.climb_speed_m_s within the tracker's limit
  // a climb's state: none (armed), holding the climb command since climb_start_W_, or spent
  // (held for the footprint's length with the nose still up: no new climb until it is down)
  enum class Climb { kNone, kHolding, kSpent };
  Climb climb_{Climb::kNone};
  bool climb_ended_{false};  // a climb's hold ended since the last plan
  Eigen::Vector2d climb_start_W_{Eigen::Vector2d::Zero()};
  Eigen::Vector2d goal_W_;
  common::Trajectory trajectory_;
  std::vector<Eigen::Vector2d> waypoints_W_;
  double next_plan_s_{0.0};
  double last_valid_plan_s_{0.0};
  bool force_replan_{false};
  bool map_check_pending_{false};  // a map update not yet checked against the plan
  // last time the robot moved (left kStallDistance_m of last_moving_W_) or was meant to stand
  // still, and where it was then
  double last_moving_s_{0.0};
  Eigen::Vector2d last_moving_W_{Eigen::Vector2d::Zero()};
  double free_drive_until_s_{-1.0};  // end of the freeing drive being followed
  // end of the narrows of the pose-search way being followed (NavigationPlan::commit_until_s):
  // no periodic replans before it
  double committed_until_s_{-1.0};
  Statistics statistics_;
  std::optional<CostMap> cost_map_;                     // of the map last seen, once needed
  const common::GridLayers* cost_map_source_{nullptr};  // that map
};

}  // namespace trav::planner
