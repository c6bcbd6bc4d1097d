#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "sim/moving_obstacles.h"

namespace trav::sim {

/// Settings of the social-force model (Helbing and Molnar, 1995).
struct SocialForceSettings {
  double relaxation_time_s{0.5};  ///< tau: how fast a walker returns to its desired velocity [s]
  double repulsion_m_s2{3.0};     ///< A: the push at the personal distance [m/s^2]
  double repulsion_range_m{0.2};  ///< B: how fast the push fades beyond it [m]
  double max_speed_factor{1.3};   ///< a walker never exceeds this times its walking speed
  double arrival_radius_m{0.3};   ///< a waypoint within this is reached [m]
};

/// Reactive walkers: the movers with a personal distance (MovingObstacle) walk their
/// waypoints in order (at the last one they turn back, or start again with loop: cycle; with loop:
/// none they stop there), each driven towards its next waypoint at its speed and pushed away from
/// every other mover and from the robot by a force that grows exponentially as the gap between
/// footprints shrinks below its personal distance. Scripted movers push but are not pushed.
/// Deterministic: semi-implicit Euler steps of the caller's size.
class SocialForceCrowd {
 public:
  /// One reactive walker's state.
  struct Walker {
    std::size_t index{0};  ///< in the movers
    Eigen::Vector2d p_W{Eigen::Vector2d::Zero()};
    Eigen::Vector2d v_W{Eigen::Vector2d::Zero()};
    double yaw{0.0};        ///< heading: of its latest motion, towards its first target at rest
    std::size_t target{1};  ///< waypoint it walks to
    int direction{1};       ///< +1 forwards through the waypoints, -1 back
    bool stopped{false};    ///< reached the end of a path without loop
  };

  /// The walkers among `movers`, each at its first waypoint and at rest.
  explicit SocialForceCrowd(const std::vector<MovingObstacle>& movers,
                            const SocialForceSettings& settings = {});

  /// Advances the walkers by dt_s from time t_s: `positions_W` holds every mover's position now
  /// (the walkers' own are taken from their state), the robot stands at robot_W with the footprint
  /// radius robot_radius_m. Walkers wait at their first waypoint until their start delay has
  /// passed.
  void Step(double t_s, double dt_s, const std::vector<Eigen::Vector2d>& positions_W,
            const Eigen::Vector2d& robot_W, double robot_radius_m);

  const std::vector<Walker>& walkers() const { return walkers_; }
  bool empty() const { return walkers_.empty(); }

 private:
  std::vector<MovingObstacle> movers_;
  SocialForceSettings settings_;
  std::vector<Walker> walkers_;
};

}  // namespace trav::sim
