#include "sim/actors/social_force.h"

#include <cmath>
#include <variant>

namespace trav::sim {
namespace {

constexpr double kMovingSpeed_m_s = 0.05;  // slower than this, a walker keeps its heading

}  // namespace

SocialForceCrowd::SocialForceCrowd(const std::vector<MovingObstacle>& movers,
                                   const SocialForceSettings& settings)
    : movers_(movers), settings_(settings) {
  for (std::size_t i = 0; i < movers_.size(); ++i) {
    if (movers_[i].personal_distance_m <= 0.0) continue;
    const auto& path = std::get<WaypointMotion>(movers_[i].motion);
    Walker walker;
    walker.index = i;
    walker.p_W = path.waypoints_W.front();
    walker.target = path.waypoints_W.size() > 1 ? 1 : 0;
    walker.stopped = path.waypoints_W.size() < 2;
    if (!walker.stopped) {
      const Eigen::Vector2d first_leg = path.waypoints_W[1] - path.waypoints_W[0];
      walker.yaw = std::atan2(first_leg.y(), first_leg.x());
    }
    walkers_.push_back(walker);
  }
}

void SocialForceCrowd::Step(double t_s, double dt_s,
                            const std::vector<Eigen::Vector2d>& positions_W,
                            const Eigen::Vector2d& robot_W, double robot_radius_m) {
  std::vector<Eigen::Vector2d> now = positions_W;
  for (const Walker& walker : walkers_) now[walker.index] = walker.p_W;
  for (Walker& walker : walkers_) {
    const MovingObstacle& self = movers_[walker.index];
    const auto& path = std::get<WaypointMotion>(self.motion);
    const double radius = MoverFootprintRadius(self);
    if (t_s < path.start_delay_s) continue;

    // the next waypoint: turn back, start again or stop at the end of the path
    const std::vector<Eigen::Vector2d>& points = path.waypoints_W;
    while (!walker.stopped &&
           (points[walker.target] - walker.p_W).norm() < settings_.arrival_radius_m) {
      const long next = static_cast<long>(walker.target) + walker.direction;
      if (next >= 0 && next < static_cast<long>(points.size())) {
        walker.target = static_cast<std::size_t>(next);
      } else if (path.loop == WaypointLoop::kPingPong) {
        walker.direction = -walker.direction;
        walker.target =
            static_cast<std::size_t>(static_cast<long>(walker.target) + walker.direction);
      } else if (path.loop == WaypointLoop::kCycle) {
        walker.target = 0;
      } else {
        walker.stopped = true;
      }
    }
    Eigen::Vector2d desired = Eigen::Vector2d::Zero();
    if (!walker.stopped) {
      const Eigen::Vector2d to_target = points[walker.target] - walker.p_W;
      if (to_target.norm() > 1e-9) desired = path.speed_m_s * to_target.normalized();
    }
    Eigen::Vector2d force = (desired - walker.v_W) / settings_.relaxation_time_s;

    // pushed by every other mover and by the robot
    auto push = [&](const Eigen::Vector2d& other_W, double other_radius_m) {
      const Eigen::Vector2d away = walker.p_W - other_W;
      const double distance = away.norm();
      if (distance < 1e-9) return;
      const double gap = distance - radius - other_radius_m;
      force += settings_.repulsion_m_s2 *
               std::exp((self.personal_distance_m - gap) / settings_.repulsion_range_m) * away /
               distance;
    };
    for (std::size_t j = 0; j < now.size(); ++j) {
      if (j != walker.index) push(now[j], MoverFootprintRadius(movers_[j]));
    }
    push(robot_W, robot_radius_m);

    walker.v_W += dt_s * force;
    const double max_speed = settings_.max_speed_factor * path.speed_m_s;
    if (walker.v_W.norm() > max_speed) walker.v_W *= max_speed / walker.v_W.norm();
    walker.p_W += dt_s * walker.v_W;
    if (walker.v_W.norm() > kMovingSpeed_m_s)
      walker.yaw = std::atan2(walker.v_W.y(), walker.v_W.x());
  }
}

}  // namespace trav::sim
