#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "sim/moving_obstacles.h"

namespace trav::scenarios {

/// How generated movers move.
enum class TrafficBehaviour {
  kRandomWalk,  ///< pedestrians walking at random inside discs along the route
  kCrossing,    ///< pedestrians crossing the route at constant velocity, timed to meet the robot
};

/// Scenario key `traffic`: movers generated from a count, a speed and a seed, so that a batch can
/// sweep the density and speed of moving obstacles.
struct TrafficSettings {
  int count{0};           ///< movers, >= 0
  double speed_m_s{1.0};  ///< walking speed [m/s], in (0, 3]
  TrafficBehaviour behaviour{TrafficBehaviour::kRandomWalk};
  std::uint64_t seed{1};
  /// Random walkers: radius of each walker's disc [m], > 0.
  double area_radius_m{2.5};
  /// No mover is closer than this to the start or the goal at time 0 [m] (plus its own radius).
  double keep_clear_m{2.0};
};

/// Checks the settings. @throws common::InputError naming the `traffic.<field>` key and value.
void ValidateTrafficSettings(const TrafficSettings& traffic);

/// The movers of `traffic` for a route from `start_W` to `goal_W`: pedestrian capsules named
/// traffic_0, traffic_1, ... Random walkers get discs centred at a uniform fraction in [0.2, 0.8]
/// of the route and a uniform lateral offset within 4 m of it, redrawn until the disc stays
/// `keep_clear_m` away from start and goal. Crossers start 6 to 10 m to either side of a uniform
/// fraction in [0.25, 0.75] of the route, walk straight across it, and leave so as to reach it
/// when a robot at 1 m/s would. The same settings and route give the same movers.
std::vector<sim::MovingObstacle> SpawnTraffic(const TrafficSettings& traffic,
                                              const Eigen::Vector2d& start_W,
                                              const Eigen::Vector2d& goal_W);

}  // namespace trav::scenarios
