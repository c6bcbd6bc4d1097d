#include "planner/navigation/navigator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "common/enum_names.h"
#include "common/input_error.h"
#include "common/stopwatch.h"

namespace trav::planner {
namespace {

// The planner's settings with the stops of its fallbacks at the tracker's deceleration: the
// hardest the robot is asked to brake.
NavigationPlannerConfig WithTrackerBraking(NavigationPlannerConfig planner,
                                           const controller::MpcConfig& mpc) {
  planner.fallback.braking_m_s2 = mpc.max_acceleration_m_s2;
  return planner;
}

// Events replan at most this often [s]: a deviation that persists must not replan every tick.
constexpr double kMinEventInterval_s = 0.1;
// Progress stalls when the plan has asked for this speed [m/s] for kStallTime_s [s] and the robot
// has stayed within a tenth of the distance that speed covers in that time of where it was: it
// crawls, or rocks in place (its wheels against a curb it cannot climb at this speed).
constexpr double kStallSpeed_m_s = 0.3;
constexpr double kStallTime_s = 1.0;
constexpr double kStallDistance_m = 0.1 * kStallSpeed_m_s * kStallTime_s;
// A stalled robot backs off straight along its heading by the longest of these distances [m] that
// keeps the footprint clear, at this speed [m/s] (or the tracker's reverse limit if lower; none
// if the tracker may not reverse), before it replans: a run-up for the next
// attempt (a 0.12 m curb stalls the robot at 1 m/s, the planner's 1.5 m/s^2 needs 0.4 m to reach
// the 1.1 m/s that climbs it, and at the stall the front wheels are about 0.36 m past the face:
// the 0.451 m wheelbase less the rear wheel's 0.0875 m radius).
constexpr double kBackOffDistances_m[] = {1.2, 0.8, 0.4};
constexpr double kBackOffSpeed_m_s = 0.6;
// Spacing of the samples of the safety and lethal-cell checks along the plan [s].
constexpr double kCheckStep_s = 0.05;
// Giving way: movers predicted this far ahead [s] that would come within this gap of the stopped
// robot's disc [m] make it move; the drives are straight lines of these lengths [m] at this speed
// [m/s], forward or backward, after a turn in place at this yaw rate [rad/s] by one of these
// angles off the heading [rad] (a step aside), and one is taken only if it keeps at least this
// much more room [m] than standing still. The speed is a walker's pace: backing away at it, the
// robot keeps pace with a walker walking at it (at 0.6 m/s such a walker caught it:
// docs/stress.md). Each direction drives at the smaller of it and the tracker's limit that way
// (FreeDriveSpeeds); a tracker that may not reverse gives way forward only.
constexpr double kGiveWayHorizon_s = 2.0;
constexpr double kGiveWayGap_m = 0.3;
constexpr double kGiveWayDistances_m[] = {0.4, 0.8, 1.2, 1.6};
constexpr double kGiveWaySpeed_m_s = 1.0;
constexpr double kGiveWayYawRate_rad_s = 1.5;
constexpr double kGiveWayTurns_rad[] = {0.0, -M_PI / 4.0, M_PI / 4.0, -M_PI / 2.0, M_PI / 2.0};
constexpr double kGiveWayGain_m = 0.1;

double YawOf(const common::RobotState& state) {
  const Eigen::Vector3d forward = state.X_WB.linear().col(0);
  return std::atan2(forward.y(), forward.x());
}

// The first point of a freeing drive (give way, back off): the robot's pose at the state's time,
// at rest.
common::TrajectoryPoint FreeDriveStart(const common::RobotState& state) {
  common::TrajectoryPoint start;
  start.t_s = state.time_s;
  start.position_W = state.X_WB.translation().head<2>();
  start.yaw = YawOf(state);
  return start;
}

}  // namespace

void ValidateNavigationSettings(const NavigationSettings& s) {
  using common::RequireValue;
  RequireValue(s.goal_radius_m > 0.0, "goal_radius", s.goal_radius_m, "must be > 0");
  RequireValue(s.planning_rate_hz > 0.0 && s.planning_rate_hz <= 50.0, "planning_rate",
               s.planning_rate_hz, "must be in (0, 50] Hz");
  RequireValue(s.replan_deviation_m > 0.0, "replan_deviation", s.replan_deviation_m, "must be > 0");
  RequireValue(s.safety_horizon_s >= 0.0, "safety_horizon", s.safety_horizon_s, "must be >= 0");
  RequireValue(s.stuck_time_s > 0.0, "stuck_time", s.stuck_time_s, "must be > 0");
  RequireValue(s.stuck_distance_m > 0.0, "stuck_distance", s.stuck_distance_m, "must be > 0");
  RequireValue(s.near_miss_clearance_m >= 0.0, "near_miss_clearance", s.near_miss_clearance_m,
               "must be >= 0");
  RequireValue(s.mover_sensing_range_m > 0.0, "mover_sensing_range", s.mover_sensing_range_m,
               "must be > 0");
  RequireValue(s.mapping_latency_s >= 0.0, "mapping_latency", s.mapping_latency_s, "must be >= 0");
  RequireValue(s.planning_failure_time_s > 0.0, "planning_failure_time", s.planning_failure_time_s,
               "must be > 0");
  RequireValue(s.climb_speed_m_s >= 0.0, "climb_speed", s.climb_speed_m_s, "must be >= 0");
  RequireValue(s.climb_pitch_deg > 0.0 && s.climb_pitch_deg < 90.0, "climb_pitch",
               s.climb_pitch_deg, "must be in (0, 90) deg");
  RequireValue(s.climb_step_m >= 0.0, "climb_step", s.climb_step_m, "must be >= 0");
}

controller::MpcConfig PlanTrackingConfig(controller::MpcConfig mpc,
                                         const NavigationPlannerConfig& planner) {
  const DynamicLimits& limits = planner.optimizer.limits;
  mpc.max_speed_m_s = std::min(mpc.max_speed_m_s, limits.max_speed_m_s);
  mpc.min_speed_m_s = std::max(mpc.min_speed_m_s, -limits.max_speed_m_s);
  mpc.max_yaw_rate_rad_s = std::min(mpc.max_yaw_rate_rad_s, 1.2 * limits.max_yaw_rate_rad_s);
  return mpc;
}

FreeDriveSpeeds FreeDriveSpeedsFor(const controller::MpcConfig& tracking) {
  FreeDriveSpeeds speeds;
  speeds.give_way_forward_m_s = std::min(kGiveWaySpeed_m_s, tracking.max_speed_m_s);
  speeds.give_way_backward_m_s = std::min(kGiveWaySpeed_m_s, -tracking.min_speed_m_s);
  speeds.back_off_m_s = std::min(kBackOffSpeed_m_s, -tracking.min_speed_m_s);
  return speeds;
}

Navigator::Navigator(const NavigationSettings& settings, const NavigationPlannerConfig& planner,
                     const controller::MpcConfig& mpc, const Eigen::Vector2d& goal_W,
                     PathSearch search, std::unique_ptr<controller::TrajectoryTracker> tracker)
    : settings_(settings),
      planner_(WithTrackerBraking(planner, mpc), std::move(search)),
      tracker_(tracker
                   ? std::move(tracker)
                   : std::make_unique<controller::MpcTracker>(PlanTrackingConfig(mpc, planner))),
      free_drive_speeds_(FreeDriveSpeedsFor(PlanTrackingConfig(mpc, planner))),
      climb_speed_m_s_(
          std::min(settings.climb_speed_m_s, PlanTrackingConfig(mpc, planner).max_speed_m_s)),
      goal_W_(goal_W) {
  ValidateNavigationSettings(settings_);
}

double Navigator::time_without_plan_s(double now_s) const {
  // a committed way is a valid plan until its narrows end
  return std::max(0.0, now_s - std::max(last_valid_plan_s_, committed_until_s_));
}

NavigatorTick Navigator::Update(const common::RobotState& state, const common::GridLayers* map,
                                bool map_updated, const std::vector<MovingObstacle>& movers) {
  NavigatorTick tick;
  if (map_updated || map != cost_map_source_) cost_map_.reset();
  cost_map_source_ = map;
  // a freeing drive (give way, back off) is followed to its end, then the robot replans; but a map
  // update may show an obstacle on it (a walker standing behind the robot, which no track
  // reports): then the robot chooses again from where it is, or stops if no drive keeps more room
  // than standing still
  bool driving_free = state.time_s < free_drive_until_s_;
  if (driving_free && map != nullptr && map_updated &&
      !WayKeepsClear(state.time_s, free_drive_until_s_, CostMapOf(*map))) {
    if (std::optional<common::Trajectory> drive = GiveWay(state, *map, movers)) {
      StartFreeDrive(std::move(*drive), state.time_s);
      ++statistics_.give_ways;
    } else {
      free_drive_until_s_ = state.time_s;
      force_replan_ = true;
      ++statistics_.safety_stops;
      tick.safety_stop = true;
      climb_ = Climb::kNone;
      return tick;
    }
  }
  ReplanReason reason =
      driving_free ? ReplanReason::kNone : ReasonToReplan(state, map, map_updated);
  if (reason == ReplanReason::kStalled && map != nullptr) {
    if (std::optional<common::Trajectory> drive = BackOff(state, *map)) {
      StartFreeDrive(std::move(*drive), state.time_s);
      ++statistics_.back_offs;
      driving_free = true;
      reason = ReplanReason::kNone;
    }
  }
  if (reason != ReplanReason::kNone && map != nullptr) {
    Replan(state, *map, movers, reason);
    tick.replan = reason;
  }
  if (!driving_free) {
    // no plan, or the plan was found unsafe and no new one has replaced it: stand still rather
    // than chase a stale reference, unless a mover closes in
    bool stopped = trajectory_.empty() || force_replan_;
    if (!stopped && !AheadIsSafe(state.time_s, map, movers)) {
      ++statistics_.safety_stops;
      force_replan_ = true;
      tick.safety_stop = true;
      stopped = true;
    }
    if (stopped) {
      std::optional<common::Trajectory> escape =
          map != nullptr ? GiveWay(state, *map, movers) : std::nullopt;
      if (!escape) {
        climb_ = Climb::kNone;
        return tick;
      }
      StartFreeDrive(std::move(*escape), state.time_s);
      ++statistics_.give_ways;
    }
  }
  tick.solved = tracker_->SolveDue(state.time_s);
  const common::Stopwatch control_start;
  tick.command = tracker_->Command(state);
  if (tick.solved) statistics_.control_ms.push_back(control_start.ElapsedMilliseconds());
  tick.climbing = HoldsClimb(state, map, tick.command);
  if (tick.climbing) tick.command = common::Twist2{climb_speed_m_s_, 0.0};
  return tick;
}

bool Navigator::HoldsClimb(const common::RobotState& state, const common::GridLayers* map,
                           const common::Twist2& command) {
  if (climb_speed_m_s_ <= 0.0 || map == nullptr) {
    climb_ = Climb::kNone;
    return false;
  }
  // pitch is positive nose down (REP-103)
  const bool nose_up = -common::ToRollPitchYaw(state.X_WB.linear()).pitch >=
                       settings_.climb_pitch_deg * M_PI / 180.0;
  const Eigen::Vector2d p_W = state.X_WB.translation().head<2>();
  const common::Footprint& footprint = planner_.config().footprint;
  switch (climb_) {
    case Climb::kHolding:
      // until the robot has driven its length, by which its rear wheels have climbed, whatever its
      // pitch meanwhile (it falls as the rear wheels climb) and however slowly the tracker asks
      // to go on (a replan at the face starts from the slowed robot); a stall's back-off
      // (the tracker reversing) or a stop ends it
      if (command.v > 0.0 && (p_W - climb_start_W_).norm() <= 2.0 * footprint.half_length_m) {
        return true;
      }
      climb_ = command.v > 0.0 && nose_up ? Climb::kSpent : Climb::kNone;
      // the plan was left: a new one at once, from the measured rates
      next_plan_s_ = std::min(next_plan_s_, state.time_s);
      climb_ended_ = true;
      return false;
    case Climb::kSpent:
      if (!nose_up) climb_ = Climb::kNone;
      return false;
    case Climb::kNone:
      if (!nose_up || command.v < kStallSpeed_m_s ||
          !StepWithinReach(*map, p_W, footprint.CircumscribedRadius()) ||
          !StraightDrive(state, *map, 2.0 * footprint.half_length_m, climb_speed_m_s_)) {
        return false;
      }
      climb_ = Climb::kHolding;
      climb_start_W_ = p_W;
      ++statistics_.step_climbs;
      return true;
  }
  return false;
}

bool Navigator::StepWithinReach(const common::GridLayers& map, const Eigen::Vector2d& p_W,
                                double reach_m) const {
  const std::string& layer = planner_.config().search.speed.roughness_layer;
  if (!map.Has(layer)) return false;
  const Eigen::MatrixXf& roughness = map.Layer(layer);
  const common::GridGeometry& g = map.geometry();
  const int cells = static_cast<int>(std::ceil(reach_m / g.resolution_m));
  for (int dy = -cells; dy <= cells; ++dy) {
    for (int dx = -cells; dx <= cells; ++dx) {
      const Eigen::Vector2d q_W = p_W + g.resolution_m * Eigen::Vector2d(dx, dy);
      const std::optional<Eigen::Vector2i> cell = g.CellIndex(q_W);
      if (cell && (q_W - p_W).norm() <= reach_m &&
          StepHeightOfRoughness(roughness(cell->x(), cell->y())) >= settings_.climb_step_m) {
        return true;
      }
    }
  }
  return false;
}

void Navigator::StartFreeDrive(common::Trajectory drive, double now_s) {
  trajectory_ = std::move(drive);
  tracker_->SetReference(trajectory_);
  free_drive_until_s_ = trajectory_.end_time();
  // a committed way is given up here: it was a valid plan until now
  committed_until_s_ = std::min(committed_until_s_, now_s);
  force_replan_ = true;  // replan once the drive ends
}

FallbackConfig Navigator::FreeDriveConfig(double speed_m_s) const {
  FallbackConfig drive = planner_.config().fallback;
  drive.creep_speed_m_s = speed_m_s;
  drive.creep_yaw_rate_rad_s = kGiveWayYawRate_rad_s;
  return drive;
}

std::optional<common::Trajectory> Navigator::BackOff(const common::RobotState& state,
                                                     const common::GridLayers& map) {
  if (free_drive_speeds_.back_off_m_s <= 0.0) return std::nullopt;  // the tracker may not reverse
  for (const double length : kBackOffDistances_m) {
    if (std::optional<common::Trajectory> drive =
            StraightDrive(state, map, -length, free_drive_speeds_.back_off_m_s)) {
      return drive;
    }
  }
  return std::nullopt;
}

std::optional<common::Trajectory> Navigator::StraightDrive(const common::RobotState& state,
                                                           const common::GridLayers& map,
                                                           double length_m, double speed_m_s) {
  const common::TrajectoryPoint start = FreeDriveStart(state);
  const Eigen::Vector2d forward_W(std::cos(start.yaw), std::sin(start.yaw));
  const CostMap& costs = CostMapOf(map);
  common::Trajectory drive =
      CreepAlong(start, {start.position_W, start.position_W + length_m * forward_W}, length_m < 0.0,
                 FreeDriveConfig(speed_m_s));
  if (!KeepsClear(costs.field(), drive, BodyPointsOn(costs),
                  planner_.config().optimizer.clearance_m)) {
    return std::nullopt;
  }
  return drive;
}

std::optional<common::Trajectory> Navigator::GiveWay(const common::RobotState& state,
                                                     const common::GridLayers& map,
                                                     const std::vector<MovingObstacle>& movers) {
  const double now = state.time_s;
  const double robot_radius = planner_.config().optimizer.robot_radius_m;
  // the smallest gap between the robot's disc, where `trajectory` puts it (still at `still_W`
  // without one), and the movers' over [from_s, to_s]
  auto smallest_gap = [&](const common::Trajectory* trajectory, const Eigen::Vector2d& still_W,
                          double from_s, double to_s) {
    double smallest = std::numeric_limits<double>::infinity();
    for (double t = from_s; t <= to_s; t += 2.0 * kCheckStep_s) {
      const Eigen::Vector2d p_W =
          trajectory != nullptr ? trajectory->Sample(t).position_W : still_W;
      for (const MovingObstacle& mover : movers) {
        smallest =
            std::min(smallest, (p_W - mover.PositionAt(t)).norm() - robot_radius - mover.radius_m);
      }
    }
    return smallest;
  };
  const Eigen::Vector2d here_W = state.X_WB.translation().head<2>();
  // only movers closing in: the gap standing still shrinks below kGiveWayGap_m (a mover standing
  // beside the robot is waited for)
  const double standing = smallest_gap(nullptr, here_W, now, now + kGiveWayHorizon_s);
  if (standing >= kGiveWayGap_m ||
      standing >= smallest_gap(nullptr, here_W, now, now) - kGiveWayGain_m) {
    return std::nullopt;
  }
  const common::TrajectoryPoint start = FreeDriveStart(state);
  const NavigationPlannerConfig& config = planner_.config();
  const CostMap& costs = CostMapOf(map);
  const std::vector<Eigen::Vector2d> body_B = BodyPointsOn(costs);
  std::optional<common::Trajectory> best;
  double best_gap = standing + kGiveWayGain_m;
  for (const double sign : {-1.0, 1.0}) {
    const double speed_m_s = sign < 0.0 ? free_drive_speeds_.give_way_backward_m_s
                                        : free_drive_speeds_.give_way_forward_m_s;
    if (speed_m_s <= 0.0) continue;
    const FallbackConfig drive = FreeDriveConfig(speed_m_s);
    for (const double turn : kGiveWayTurns_rad) {
      const double yaw = start.yaw + turn;
      const Eigen::Vector2d forward_W(std::cos(yaw), std::sin(yaw));
      for (const double length : kGiveWayDistances_m) {
        common::Trajectory candidate =
            CreepAlong(start, {here_W, here_W + sign * length * forward_W}, sign < 0.0, drive);
        const double gap = smallest_gap(&candidate, here_W, now, now + kGiveWayHorizon_s);
        if (gap > best_gap &&
            KeepsClear(costs.field(), candidate, body_B, config.optimizer.clearance_m)) {
          best_gap = gap;
          best = std::move(candidate);
        }
      }
    }
  }
  return best;
}

ReplanReason Navigator::ReasonToReplan(const common::RobotState& state,
                                       const common::GridLayers* map, bool map_updated) {
  // a map update during the event blackout is checked when the blackout ends, not dropped
  map_check_pending_ = map_check_pending_ || map_updated;
  const double now = state.time_s;
  if (map == nullptr) return ReplanReason::kNone;
  if (trajectory_.empty()) return now >= next_plan_s_ ? ReplanReason::kFirst : ReplanReason::kNone;
  if (now >= next_plan_s_ && now >= committed_until_s_) return ReplanReason::kPeriodic;
  if (now < next_plan_s_ - 1.0 / settings_.planning_rate_hz + kMinEventInterval_s) {
    return ReplanReason::kNone;
  }
  if (force_replan_) return ReplanReason::kSafetyStop;
  const Eigen::Vector2d position_W = state.X_WB.translation().head<2>();
  // a held climb means to move at the climb speed, whatever the plan
  const double planned_speed =
      climb_ == Climb::kHolding ? climb_speed_m_s_ : std::abs(trajectory_.Sample(now).v);
  if (planned_speed < kStallSpeed_m_s || (position_W - last_moving_W_).norm() > kStallDistance_m) {
    last_moving_s_ = now;
    last_moving_W_ = position_W;
  } else if (now - last_moving_s_ > kStallTime_s) {
    last_moving_s_ = now;
    return ReplanReason::kStalled;
  }
  if ((trajectory_.Sample(now).position_W - position_W).norm() > settings_.replan_deviation_m) {
    return ReplanReason::kDeviation;
  }
  if (map_check_pending_) {
    map_check_pending_ = false;
    for (double t = now; t <= trajectory_.end_time(); t += kCheckStep_s) {
      if (CostMapOf(*map).LethalAt(trajectory_.Sample(t).position_W)) {
        return ReplanReason::kNewLethalCells;
      }
    }
    // a way followed without periodic replans keeps its footprint's clearance on the new map
    if (now < committed_until_s_ && !WayKeepsClear(now, committed_until_s_, CostMapOf(*map))) {
      return ReplanReason::kNewLethalCells;
    }
  }
  return ReplanReason::kNone;
}

void Navigator::Replan(const common::RobotState& state, const common::GridLayers& map,
                       const std::vector<MovingObstacle>& movers, ReplanReason reason) {
  const double now = state.time_s;
  const TrajectoryOptimizerConfig& optimizer = planner_.config().optimizer;
  // the start: the measured pose; the rates of the plan being followed when the robot is on it
  // (a smooth splice), else the measured ones, within the limits
  common::TrajectoryPoint start;
  start.t_s = now;
  start.position_W = state.X_WB.translation().head<2>();
  start.yaw = YawOf(state);
  // (a robot that holds or has just held a climb has left the plan: its measured rates start the
  // next one, not the plan's, which it outran)
  const bool on_plan = climb_ != Climb::kHolding && !climb_ended_ && !trajectory_.empty() &&
                       (trajectory_.Sample(now).position_W - start.position_W).norm() <=
                           settings_.replan_deviation_m;
  climb_ended_ = false;
  if (on_plan) {
    const common::TrajectoryPoint planned = trajectory_.Sample(now);
    start.v = planned.v;
    start.omega = planned.omega;
    start.acceleration = planned.acceleration;
  } else {
    start.v = state.v_WB_B.x();
    start.omega = state.w_WB_B.z();
  }
  const double v_max = 0.99 * optimizer.limits.max_speed_m_s;
  const double omega_max = 0.99 * optimizer.limits.max_yaw_rate_rad_s;
  const double a_max = 0.99 * optimizer.limits.max_acceleration_m_s2;
  start.v = std::clamp(start.v, -v_max, v_max);
  start.omega = std::clamp(start.omega, -omega_max, omega_max);
  start.acceleration = std::clamp(start.acceleration, -a_max, a_max);

  const NavigationPlan plan =
      planner_.Plan(CostMapOf(map), start, goal_W_, movers, on_plan ? &trajectory_ : nullptr);
  map_check_pending_ = false;  // the new plan saw the latest map
  ++statistics_.plans;
  if (reason != ReplanReason::kPeriodic && reason != ReplanReason::kFirst) {
    ++statistics_.replans_on_events;
  }
  statistics_.planning_ms.push_back(1e3 * (plan.search_time_s + plan.optimization_time_s));
  statistics_.last_status = common::NameOf(plan.status);
  if (plan.status == NavigationStatus::kOptimizerFailed || plan.fallback != Fallback::kNone) {
    const OptimizationDiagnostics& d = plan.optimized.diagnostics;
    statistics_.last_status += " (" + d.worst_constraint + " violated by " +
                               std::to_string(static_cast<int>(100.0 * d.max_violation)) +
                               " %, end " + std::to_string(d.terminal_error_m) +
                               " m from the goal)";
  }
  if (plan.fallback != Fallback::kNone) {
    statistics_.last_status += ", " + std::string(common::NameOf(plan.fallback));
    ++statistics_.fallbacks[static_cast<std::size_t>(plan.fallback)];
  }
  const bool leads_to_goal = plan.status == NavigationStatus::kPlanned ||
                             plan.status == NavigationStatus::kPlannedToNearest;
  const bool usable = plan.has_trajectory() && (leads_to_goal || plan.fallback != Fallback::kNone);
  // a plan to the substitute of an unreachable goal that ends where the robot already is leads
  // nowhere: it is followed, but the time without a plan keeps running
  const bool leads_nowhere =
      plan.status == NavigationStatus::kPlannedToNearest && plan.has_trajectory() &&
      (plan.optimized.trajectory.points().back().position_W - start.position_W).norm() <=
          settings_.goal_radius_m;
  if (usable) {
    trajectory_ = plan.optimized.trajectory;
    waypoints_W_ = plan.waypoints_W;
    tracker_->SetReference(trajectory_);
    // a manoeuvre that only frees the robot does not count as a plan: the patience keeps running
    if (leads_to_goal && !leads_nowhere) last_valid_plan_s_ = now;
    committed_until_s_ = plan.commit_until_s.value_or(-1.0);
    force_replan_ = false;
  } else {
    ++statistics_.failed_plans;
  }
  next_plan_s_ = now + 1.0 / settings_.planning_rate_hz;
}

bool Navigator::WayKeepsClear(double from_s, double to_s, const CostMap& costs) const {
  const NavigationPlannerConfig& config = planner_.config();
  std::vector<common::TrajectoryPoint> ahead;
  for (double t = from_s; t <= to_s; t += kCheckStep_s) {
    ahead.push_back(trajectory_.Sample(t));
  }
  return KeepsClear(costs.field(), common::Trajectory(std::move(ahead)), BodyPointsOn(costs),
                    config.optimizer.clearance_m);
}

std::vector<Eigen::Vector2d> Navigator::BodyPointsOn(const CostMap& costs) const {
  const NavigationPlannerConfig& config = planner_.config();
  return BodyPoints_B(config.footprint, costs.geometry().resolution_m,
                      config.optimizer.clearance_m);
}

const CostMap& Navigator::CostMapOf(const common::GridLayers& map) {
  if (!cost_map_) cost_map_.emplace(map, planner_.config().SearchConfig(), planner_.Remember(map));
  return *cost_map_;
}

bool Navigator::AheadIsSafe(double now_s, const common::GridLayers* map,
                            const std::vector<MovingObstacle>& movers) {
  const NavigationPlannerConfig& config = planner_.config();
  const double end = std::min(trajectory_.end_time(), now_s + settings_.safety_horizon_s);
  const Eigen::Vector2d here_W = trajectory_.Sample(now_s).position_W;
  for (double t = now_s; t <= end; t += kCheckStep_s) {
    const Eigen::Vector2d p_W = trajectory_.Sample(t).position_W;
    // lethal cells under the robot itself (a mapping artefact) do not stop it: only those ahead
    const bool ahead = (p_W - here_W).norm() > config.optimizer.robot_radius_m;
    if (map != nullptr && ahead && CostMapOf(*map).LethalAt(p_W)) return false;
    for (const MovingObstacle& mover : movers) {
      if ((p_W - mover.PositionAt(t)).norm() < config.optimizer.robot_radius_m + mover.radius_m) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace trav::planner
