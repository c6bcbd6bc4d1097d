#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/archive.h"
#include "common/pose.h"
#include "common/trajectory.h"
#include "planner/cost_field.h"

namespace trav::planner {

/// Settings of the slow manoeuvres the planner falls back on when trajectory optimisation fails
/// (scenario key `planner.fallback`; docs/navigation.md).
struct FallbackConfig {
  double creep_speed_m_s{0.3};       ///< speed along the search path or backwards [m/s], > 0
  double creep_yaw_rate_rad_s{0.6};  ///< yaw rate of the turns in place [rad/s], > 0
  double back_out_distance_m{0.6};   ///< longest reverse drive [m], > 0
  /// The footprint's own way (SearchPoses) leads to the point this far along the search path [m],
  /// > 0.
  double search_reach_m{4.0};
  int search_expansions{20000};  ///< the poses it expands at most, >= 0 (0: no such search)
  double output_step_s{0.02};    ///< sample spacing [s], > 0
  /// Deceleration of a stop (StopFrom) [m/s^2], > 0: not a key; the navigator sets its tracker's
  /// max_acceleration.
  double braking_m_s2{2.0};

  /// The keys of scenario section `planner.fallback` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("creep_speed", &creep_speed_m_s, {0.01, 5});
    a->Field("creep_yaw_rate", &creep_yaw_rate_rad_s, {0.01, 10});
    a->Field("back_out_distance", &back_out_distance_m, {0.01, 10});
    a->Field("search_reach", &search_reach_m, {0.1, 50});
    a->Field("search_expansions", &search_expansions, {0, 10000000});
  }
};

/// Checks a config. @throws common::InputError naming the key (relative: "creep_speed").
void ValidateFallbackConfig(const FallbackConfig& config);

/// The robot brought to rest from the start's motion: straight along its heading at
/// `braking_m_s2`, its yaw rate brought to zero over the same time. Sampled every `output_step_s`
/// from start.t_s, the start first, the last point at rest (the start alone, at rest, if it does
/// not move forward or backward).
common::Trajectory StopFrom(const common::TrajectoryPoint& start, const FallbackConfig& config);

/// The robot brought to rest along `path`, the trajectory it is following (its pose at start.t_s
/// the start's): at `braking_m_s2` from start.v, each sample at the distance along the path's
/// positions that the stop has covered by then, with the path's yaw there and its yaw rate scaled
/// to the stop's speed. Sampled every `output_step_s` from start.t_s, the last point at rest.
/// Nothing when the path, from start.t_s to its end, is shorter than the stop, or the start is
/// at rest.
std::optional<common::Trajectory> StopAlong(const common::Trajectory& path,
                                            const common::TrajectoryPoint& start,
                                            const FallbackConfig& config);

/// StopFrom `start`, or StopAlong `followed` (unless null) where that keeps the footprint's body
/// points farther from lethal cells (SmallestGap).
common::Trajectory SaferStop(const CostField& field, const common::TrajectoryPoint& start,
                             const common::Trajectory* followed,
                             const std::vector<Eigen::Vector2d>& body_points_B,
                             const FallbackConfig& config);

/// The smallest distance of the footprint's body points to lethal cells over the trajectory's
/// points (FootprintDistance) [m]; infinity without points.
double SmallestGap(const CostField& field, const common::Trajectory& trajectory,
                   const std::vector<Eigen::Vector2d>& body_points_B);

/// A slow trajectory through `waypoints_W` from the start's pose: at the start and at each vertex
/// the robot turns in place to the next segment's heading at `creep_yaw_rate`, then drives the
/// segment straight at `creep_speed`, forward, or backward (facing away from it) when `reverse`.
/// Sampled every `output_step_s` from start.t_s; rates are piecewise constant. The first waypoint
/// is where the robot is (start.position_W); an empty or single-point list gives the start alone.
common::Trajectory CreepAlong(const common::TrajectoryPoint& start,
                              const std::vector<Eigen::Vector2d>& waypoints_W, bool reverse,
                              const FallbackConfig& config);

/// A slow trajectory through `poses` (SearchPoses's ways) from the start's pose: to each pose the
/// robot turns in place to its yaw (the shorter way) at `creep_yaw_rate`, then drives straight to
/// its position at `creep_speed`, forward or backward along that yaw.
common::Trajectory CreepThrough(const common::TrajectoryPoint& start,
                                const std::vector<common::Pose2>& poses,
                                const FallbackConfig& config);

/// A turn in place at the start's position from its yaw to `yaw` (the shorter way round).
common::Trajectory TurnInPlace(const common::TrajectoryPoint& start, double yaw,
                               const FallbackConfig& config);

/// True if the footprint's body points never come closer to lethal cells than
/// min(min_clearance_m, their gap at the trajectory's start), sampled at every point: a manoeuvre
/// may start too close, never get closer.
bool KeepsClear(const CostField& field, const common::Trajectory& trajectory,
                const std::vector<Eigen::Vector2d>& body_points_B, double min_clearance_m);

}  // namespace trav::planner
