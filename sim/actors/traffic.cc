#include "sim/actors/traffic.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include "common/input_error.h"
#include "common/random.h"

namespace trav::sim {
namespace {

constexpr double kLateralSpread_m = 4.0;  // random walkers' discs: centre within this of the route
constexpr double kCrossingMin_m = 6.0;    // crossers start this far to the side, at least
constexpr double kCrossingMax_m = 10.0;   // and at most
constexpr double kRobotSpeed_m_s = 1.0;   // the speed crossers are timed for
constexpr int kDrawsPerMover = 100;
constexpr double kStreamInterval_s = 2.0;    // flow and head-on: one pedestrian every this
constexpr double kFlowOffset_m = 8.0;        // flow: where the crossers start, to the side
constexpr double kAlongRouteSpread_m = 1.0;  // head-on, overtaking: within this of the route
constexpr double kReactiveOffset_m = 6.0;    // reactive: the turning points, to either side
constexpr double kPersonalDistance_m = 0.8;  // reactive: the gap they keep
constexpr double kPathCheckLength_m = 20.0;  // paths are checked this far from where they start
constexpr double kPathCheckStep_m = 0.25;

// A mover of the shape, standing still.
MovingObstacle Shaped(TrafficShape shape) {
  MovingObstacle mover;  // a pedestrian capsule by default
  if (shape == TrafficShape::kCart) {
    mover.shape = MoverShape::kBox;
    mover.box_half_extents_m = {0.5, 0.35};
    mover.half_height_m = 0.5;
  } else if (shape == TrafficShape::kBox) {
    mover.shape = MoverShape::kBox;
    mover.box_half_extents_m = {0.3, 0.3};
    mover.half_height_m = 0.4;
  }
  return mover;
}

// Whether a mover keeps clear of start and goal at time 0 and of static obstacles on its way.
bool Fits(const MovingObstacle& mover, const Eigen::Vector2d& start_W,
          const Eigen::Vector2d& goal_W, double clear_m, const FreeDisc& free) {
  auto clear_of_ends = [&](const Eigen::Vector2d& p, double margin_m) {
    return (p - start_W).norm() >= clear_m + margin_m && (p - goal_W).norm() >= clear_m + margin_m;
  };
  if (const auto* walk = std::get_if<RandomWalkMotion>(&mover.motion)) {
    // anywhere in its disc, at any time
    return clear_of_ends(walk->area_centre_W, walk->area_radius_m) &&
           (!free || free(walk->area_centre_W, walk->area_radius_m + MoverFootprintRadius(mover)));
  }
  MoverTrack track(mover);
  if (!clear_of_ends(track.PlanarStateAt(0.0).p_W, 0.0)) return false;
  if (!free) return true;
  // walking speed and departure of a constant-velocity or waypoint motion
  double speed = 0.0, departure_s = 0.0;
  if (const auto* crossing = std::get_if<ConstantVelocityMotion>(&mover.motion)) {
    speed = crossing->velocity_W.norm();
    departure_s = crossing->start_time_s;
  } else {
    const auto& path = std::get<WaypointMotion>(mover.motion);
    speed = path.speed_m_s;
    departure_s = path.start_delay_s;
  }
  speed = std::max(speed, 1e-6);
  const double step_s = kPathCheckStep_m / speed;
  for (double t = 0.0; t <= departure_s + kPathCheckLength_m / speed; t += step_s) {
    if (!free(track.PlanarStateAt(t).p_W, MoverFootprintRadius(mover))) return false;
  }
  return true;
}

}  // namespace

void ValidateTrafficSettings(const TrafficSettings& traffic) {
  common::RequireValue(traffic.count >= 0, "count", traffic.count, "must be >= 0");
  common::RequireValue(traffic.speed_m_s > 0.0 && traffic.speed_m_s <= 3.0, "speed",
                       traffic.speed_m_s, "must be in (0, 3] m/s");
  common::RequireValue(traffic.area_radius_m > 0.0, "area_radius", traffic.area_radius_m,
                       "must be > 0");
  common::RequireValue(traffic.keep_clear_m >= 0.0, "keep_clear", traffic.keep_clear_m,
                       "must be >= 0");
}

std::vector<MovingObstacle> SpawnTraffic(const TrafficSettings& traffic,
                                         const Eigen::Vector2d& start_W,
                                         const Eigen::Vector2d& goal_W, const FreeDisc& free) {
  ValidateTrafficSettings(traffic);
  std::vector<MovingObstacle> movers;
  const Eigen::Vector2d route = goal_W - start_W;
  const double length = route.norm();
  if (traffic.count == 0 || length <= 0.0) return movers;
  const Eigen::Vector2d along = route / length;
  const Eigen::Vector2d across(-along.y(), along.x());
  common::Random random(traffic.seed);
  for (int k = 0; k < traffic.count; ++k) {
    MovingObstacle mover = Shaped(traffic.shape);
    mover.name = "traffic_" + std::to_string(k);
    const double body = MoverFootprintRadius(mover);
    const double clear = traffic.keep_clear_m + body;
    const double stagger_s = kStreamInterval_s * k;
    bool placed = false;
    for (int draw = 0; draw < kDrawsPerMover && !placed; ++draw) {
      switch (traffic.behaviour) {
        case TrafficBehaviour::kRandomWalk: {
          RandomWalkMotion walk;
          walk.seed = random.Next();
          walk.speed_m_s = traffic.speed_m_s;
          walk.area_radius_m = traffic.area_radius_m;
          walk.pause_s = {0.0, 1.0};
          walk.area_centre_W = start_W + random.Uniform(0.2, 0.8) * route +
                               random.Uniform(-kLateralSpread_m, kLateralSpread_m) * across;
          mover.motion = walk;
          break;
        }
        case TrafficBehaviour::kCrossing: {
          const double fraction = random.Uniform(0.25, 0.75);
          const double side = random.Bernoulli(0.5) ? 1.0 : -1.0;
          const double offset = random.Uniform(kCrossingMin_m, kCrossingMax_m);
          ConstantVelocityMotion crossing;
          crossing.start_W = start_W + fraction * route + side * offset * across;
          crossing.velocity_W = -side * traffic.speed_m_s * across;
          crossing.start_time_s =
              std::max(0.0, fraction * length / kRobotSpeed_m_s - offset / traffic.speed_m_s);
          mover.motion = crossing;
          break;
        }
        case TrafficBehaviour::kFlow: {
          const double side = k % 2 == 0 ? 1.0 : -1.0;
          ConstantVelocityMotion crossing;
          crossing.start_W = start_W + 0.5 * route + side * kFlowOffset_m * across +
                             random.Uniform(-0.5, 0.5) * along;
          crossing.velocity_W = -side * traffic.speed_m_s * across;
          crossing.start_time_s = stagger_s;
          mover.motion = crossing;
          break;
        }
        case TrafficBehaviour::kReactive: {
          const Eigen::Vector2d middle = start_W + random.Uniform(0.25, 0.75) * route;
          const double side = random.Bernoulli(0.5) ? 1.0 : -1.0;
          WaypointMotion walk;
          walk.waypoints_W = {middle + side * kReactiveOffset_m * across,
                              middle - side * kReactiveOffset_m * across};
          walk.speed_m_s = traffic.speed_m_s;
          walk.loop = WaypointLoop::kPingPong;
          walk.start_delay_s = random.Uniform(0.0, kStreamInterval_s);
          mover.motion = walk;
          mover.personal_distance_m = kPersonalDistance_m;
          break;
        }
        case TrafficBehaviour::kHeadOn:
        case TrafficBehaviour::kOvertaking: {
          const bool head_on = traffic.behaviour == TrafficBehaviour::kHeadOn;
          const double fraction = head_on ? random.Uniform(0.6, 0.9) : random.Uniform(0.15, 0.5);
          ConstantVelocityMotion walk;
          walk.start_W = start_W + fraction * route +
                         random.Uniform(-kAlongRouteSpread_m, kAlongRouteSpread_m) * across;
          walk.velocity_W = (head_on ? -1.0 : 1.0) * traffic.speed_m_s * along;
          walk.start_time_s = head_on ? stagger_s : 0.0;
          mover.motion = walk;
          break;
        }
      }
      placed = Fits(mover, start_W, goal_W, clear, free);
    }
    if (placed) movers.push_back(std::move(mover));
  }
  return movers;
}

}  // namespace trav::sim
