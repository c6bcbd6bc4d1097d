#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "common/archive.h"
#include "common/enum_names.h"
#include "sim/moving_obstacles.h"

namespace trav::sim {

/// How generated movers move.
enum class TrafficBehaviour {
  kRandomWalk,  ///< pedestrians walking at random inside discs along the route
  kCrossing,    ///< pedestrians crossing the route at constant velocity, timed to meet the robot
  kFlow,        ///< a stream crossing the route at its middle from both sides, 2 s apart
  kHeadOn,      ///< pedestrians walking along the route from the goal towards the start
  kOvertaking,  ///< pedestrians walking along the route ahead of the robot, towards the goal
  kReactive,    ///< pedestrians walking back and forth across the route, keeping their distance
                ///< from each other and the robot (social force, personal distance 0.8 m)
};

/// The names of TrafficBehaviour's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<TrafficBehaviour>, 6> kTrafficBehaviourNames{
    {{TrafficBehaviour::kRandomWalk, "random_walk"},
     {TrafficBehaviour::kCrossing, "crossing"},
     {TrafficBehaviour::kFlow, "flow"},
     {TrafficBehaviour::kHeadOn, "head_on"},
     {TrafficBehaviour::kOvertaking, "overtaking"},
     {TrafficBehaviour::kReactive, "reactive"}}};
constexpr const auto& EnumNames(TrafficBehaviour) { return kTrafficBehaviourNames; }

/// What generated movers look like.
enum class TrafficShape {
  kPedestrian,  ///< a capsule, radius 0.25 m, 1.7 m tall
  kCart,        ///< a box 1.0 x 0.7 x 1.0 m (long side along its motion)
  kBox,         ///< a box 0.6 x 0.6 x 0.8 m
};

/// The names of TrafficShape's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<TrafficShape>, 3> kTrafficShapeNames{
    {{TrafficShape::kPedestrian, "pedestrian"},
     {TrafficShape::kCart, "cart"},
     {TrafficShape::kBox, "box"}}};
constexpr const auto& EnumNames(TrafficShape) { return kTrafficShapeNames; }

/// Scenario key `traffic`: movers generated from a count, a speed and a seed, so that a batch can
/// sweep the density and speed of moving obstacles.
struct TrafficSettings {
  int count{0};           ///< movers, >= 0
  double speed_m_s{1.0};  ///< walking speed [m/s], in (0, 3]
  TrafficBehaviour behaviour{TrafficBehaviour::kRandomWalk};
  TrafficShape shape{TrafficShape::kPedestrian};
  std::uint64_t seed{1};
  /// Random walkers: radius of each walker's disc [m], > 0.
  double area_radius_m{2.5};
  /// No mover is closer than this to the start or the goal at time 0 [m] (plus its own radius).
  double keep_clear_m{2.0};

  /// The keys of scenario section `traffic` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("count", &count, {0, 200});
    a->Field("speed", &speed_m_s, {0, 5});
    a->Enum("behaviour", &behaviour);
    a->Enum("shape", &shape);
    a->Field("seed", &seed);
    a->Field("area_radius", &area_radius_m, {0, 500});
    a->Field("keep_clear", &keep_clear_m, {0, 100});
  }
};

/// Checks the settings. @throws common::InputError naming the key (relative: "speed") and value.
void ValidateTrafficSettings(const TrafficSettings& traffic);

/// Whether a disc (centre [m], radius [m]) in W is free of static obstacles.
using FreeDisc = std::function<bool(const Eigen::Vector2d& centre_W, double radius_m)>;

/// The movers of `traffic` for a route from `start_W` to `goal_W`, of its shape, named traffic_0,
/// traffic_1, ... Each is drawn again (up to 100 times) until its disc (random walkers)
/// or its path (the others, sampled every 0.25 m over its first 20 m) is `free`, and until it keeps
/// `keep_clear_m` plus its radius from start and goal at time 0; a mover that never fits is left
/// out. Random walkers: discs centred at a uniform fraction in [0.2, 0.8] of the route and within
/// 4 m of it. Crossers: from 6 to 10 m to either side of a fraction in [0.25, 0.75], straight
/// across, leaving so as to reach the route when a robot at 1 m/s would. Flow: crossers at the
/// middle of the route from alternate sides 8 m away, one every 2 s. Head-on: from a fraction in
/// [0.6, 0.9] towards the start, within 1 m of the route, one every 2 s. Overtaking: from a
/// fraction in [0.15, 0.5] towards the goal and on, within 1 m of the route. The same settings and
/// route give the same movers. @throws common::InputError if the settings are invalid.
std::vector<MovingObstacle> SpawnTraffic(const TrafficSettings& traffic,
                                         const Eigen::Vector2d& start_W,
                                         const Eigen::Vector2d& goal_W, const FreeDisc& free = {});

}  // namespace trav::sim
