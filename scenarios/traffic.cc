#include "scenarios/traffic.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/input_error.h"
#include "common/random.h"

namespace trav::scenarios {
namespace {

constexpr double kLateralSpread_m = 4.0;  // random walkers' discs: centre within this of the route
constexpr double kCrossingMin_m = 6.0;    // crossers start this far to the side, at least
constexpr double kCrossingMax_m = 10.0;   // and at most
constexpr double kRobotSpeed_m_s = 1.0;   // the speed crossers are timed for
constexpr int kDrawsPerMover = 100;

}  // namespace

void ValidateTrafficSettings(const TrafficSettings& traffic) {
  common::RequireValue(traffic.count >= 0, "traffic.count", traffic.count, "must be >= 0");
  common::RequireValue(traffic.speed_m_s > 0.0 && traffic.speed_m_s <= 3.0, "traffic.speed",
                       traffic.speed_m_s, "must be in (0, 3] m/s");
  common::RequireValue(traffic.area_radius_m > 0.0, "traffic.area_radius", traffic.area_radius_m,
                       "must be > 0");
  common::RequireValue(traffic.keep_clear_m >= 0.0, "traffic.keep_clear", traffic.keep_clear_m,
                       "must be >= 0");
}

std::vector<sim::MovingObstacle> SpawnTraffic(const TrafficSettings& traffic,
                                              const Eigen::Vector2d& start_W,
                                              const Eigen::Vector2d& goal_W) {
  std::vector<sim::MovingObstacle> movers;
  const Eigen::Vector2d route = goal_W - start_W;
  const double length = route.norm();
  if (traffic.count == 0 || length <= 0.0) return movers;
  const Eigen::Vector2d along = route / length;
  const Eigen::Vector2d across(-along.y(), along.x());
  common::Random random(traffic.seed);
  for (int k = 0; k < traffic.count; ++k) {
    sim::MovingObstacle mover;  // a pedestrian capsule by default
    mover.name = "traffic_" + std::to_string(k);
    const double clear = traffic.keep_clear_m + mover.radius_m;
    if (traffic.behaviour == TrafficBehaviour::kRandomWalk) {
      sim::RandomWalkMotion walk;
      walk.seed = random.Next();
      walk.speed_m_s = traffic.speed_m_s;
      walk.area_radius_m = traffic.area_radius_m;
      walk.pause_s = {0.0, 1.0};
      for (int draw = 0; draw < kDrawsPerMover; ++draw) {
        walk.area_centre_W = start_W + random.Uniform(0.2, 0.8) * route +
                             random.Uniform(-kLateralSpread_m, kLateralSpread_m) * across;
        const double gap =
            std::min((walk.area_centre_W - start_W).norm(), (walk.area_centre_W - goal_W).norm());
        if (gap >= walk.area_radius_m + clear) break;
      }
      mover.motion = walk;
    } else {
      const double fraction = random.Uniform(0.25, 0.75);
      const double side = random.Bernoulli(0.5) ? 1.0 : -1.0;
      const double offset = random.Uniform(kCrossingMin_m, kCrossingMax_m);
      sim::ConstantVelocityMotion crossing;
      crossing.start_W = start_W + fraction * route + side * offset * across;
      crossing.velocity_W = -side * traffic.speed_m_s * across;
      crossing.start_time_s =
          std::max(0.0, fraction * length / kRobotSpeed_m_s - offset / traffic.speed_m_s);
      mover.motion = crossing;
    }
    movers.push_back(std::move(mover));
  }
  return movers;
}

}  // namespace trav::scenarios
