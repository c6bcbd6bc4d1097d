#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Geometry>

#include "common/archive.h"
#include "common/enum_names.h"
#include "common/mesh.h"
#include "common/random.h"
#include "sim/terrain.h"

namespace trav::sim {

/// Shapes of moving obstacles. Every shape stands upright on the ground.
enum class MoverShape { kBox, kCylinder, kCapsule };

/// The names of MoverShape's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<MoverShape>, 3> kMoverShapeNames{
    {{MoverShape::kBox, "box"},
     {MoverShape::kCylinder, "cylinder"},
     {MoverShape::kCapsule, "capsule"}}};
constexpr const auto& EnumNames(MoverShape) { return kMoverShapeNames; }

/// How a scripted mover continues after its last waypoint.
enum class WaypointLoop {
  kNone,      ///< stops at the last waypoint and stays there
  kCycle,     ///< walks from the last waypoint straight back to the first and starts again
  kPingPong,  ///< turns back at each end: first to last, last to first, and so on
};

/// The names of WaypointLoop's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<WaypointLoop>, 3> kWaypointLoopNames{
    {{WaypointLoop::kNone, "none"},
     {WaypointLoop::kCycle, "cycle"},
     {WaypointLoop::kPingPong, "ping_pong"}}};
constexpr const auto& EnumNames(WaypointLoop) { return kWaypointLoopNames; }

/// Scripted waypoints: the mover stands at the first waypoint until `start_delay_s`, then walks the
/// waypoints in order along straight lines at constant speed. Repeated consecutive waypoints are
/// skipped; with one waypoint (or all equal) it stands still.
struct WaypointMotion {
  std::vector<Eigen::Vector2d> waypoints_W;  ///< (x, y) in W [m], at least one
  double speed_m_s{1.0};                     ///< walking speed [m/s], > 0
  WaypointLoop loop{WaypointLoop::kNone};
  double start_delay_s{0.0};  ///< time it stands at the first waypoint [s], >= 0
};

/// Constant-velocity crosser: stands at `start_W` until `start_time_s`, then moves in a straight
/// line at `velocity_W` for ever.
struct ConstantVelocityMotion {
  Eigen::Vector2d start_W{Eigen::Vector2d::Zero()};     ///< position until start_time_s [m]
  Eigen::Vector2d velocity_W{Eigen::Vector2d::Zero()};  ///< [m/s] in W
  double start_time_s{0.0};                             ///< [s], >= 0
};

/// Random walker inside a disc: starts at a random point of the disc at t = 0, walks in straight
/// lines at `speed_m_s` to random targets drawn uniformly over the disc (so it never leaves it),
/// and pauses at each target for a time drawn uniformly from `pause_s`. The draws come from
/// common::Random(seed) in a fixed order (the start's radius and angle; then per leg the target's
/// radius and angle and the pause),
/// so the path is a pure function of the parameters and the time.
struct RandomWalkMotion {
  std::uint64_t seed{1};
  Eigen::Vector2d area_centre_W{Eigen::Vector2d::Zero()};  ///< centre of the disc in W [m]
  double area_radius_m{3.0};                               ///< radius of the disc [m], > 0
  double speed_m_s{1.0};                                   ///< walking speed [m/s], > 0
  std::array<double, 2> pause_s{0.0,
                                0.0};  ///< [min, max] pause at each target [s], 0 <= min <= max
};

/// One of the three behaviours.
using MoverMotion = std::variant<WaypointMotion, ConstantVelocityMotion, RandomWalkMotion>;
/// How a mover moves, as a scenario file names it (the alternative MoverMotion holds).
enum class MotionKind { kWaypoints, kConstantVelocity, kRandomWalk };

/// The names of MotionKind's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<MotionKind>, 3> kMotionKindNames{
    {{MotionKind::kWaypoints, "waypoints"},
     {MotionKind::kConstantVelocity, "constant_velocity"},
     {MotionKind::kRandomWalk, "random_walk"}}};
constexpr const auto& EnumNames(MotionKind) { return kMotionKindNames; }

/// The kind of `motion`.
inline MotionKind KindOf(const MoverMotion& motion) {
  if (std::holds_alternative<WaypointMotion>(motion)) return MotionKind::kWaypoints;
  if (std::holds_alternative<RandomWalkMotion>(motion)) return MotionKind::kRandomWalk;
  return MotionKind::kConstantVelocity;
}

/// The motion `motion` holds as `Motion`, made so (with defaults) if it holds another.
template <typename Motion>
Motion& EmplaceMotion(MoverMotion* motion) {
  if (!std::holds_alternative<Motion>(*motion)) *motion = Motion{};
  return std::get<Motion>(*motion);
}

/// A moving obstacle: a kinematic shape that follows its motion regardless of contacts. Its own
/// frame O has its origin at the centre of the shape, z up and x along the direction of motion.
/// Defaults describe a pedestrian: a capsule of radius 0.25 m, 1.7 m tall.
struct MovingObstacle {
  /// Unique among the movers; letters, digits, '_' and '-'. The MuJoCo body and geom are named
  /// "mover_<name>".
  std::string name;
  MoverShape shape{MoverShape::kCapsule};
  double half_height_m{0.85};  ///< half the total height, capsule caps included [m], > 0
  double radius_m{0.25};       ///< cylinder and capsule radius [m], > 0 (capsules: < half height)
  /// Box half-extents along O's x (the direction of motion) and y [m], > 0.
  Eigen::Vector2d box_half_extents_m{0.3, 0.3};
  Eigen::Vector4f rgba{0.95f, 0.55f, 0.1f, 1.0f};  ///< colour in videos, components in [0, 1]
  MoverMotion motion{ConstantVelocityMotion{}};
  /// > 0: a reactive walker (waypoint motion only) that walks towards its waypoints but keeps
  /// this gap from the other movers and the robot (a social-force model run by the scenario,
  /// scenarios/social_force.h); its MoverTrack is then the path it would walk alone [m].
  double personal_distance_m{0.0};

  /// The keys of an item of scenario section `moving_obstacles` (common/archive.h): the shape, and
  /// the keys of the motion that `motion` names.
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("name", &name);
    a->Enum("shape", &shape);
    a->Field("radius", &radius_m, {0.01, 10});
    a->Field("half_height", &half_height_m, {0.01, 10});
    a->Field("box_half_extents", &box_half_extents_m, {0.01, 10});
    MotionKind kind = KindOf(motion);
    a->Enum("motion", &kind);
    switch (kind) {
      case MotionKind::kWaypoints: {
        auto& w = EmplaceMotion<WaypointMotion>(&motion);
        a->Field("waypoints", &w.waypoints_W, {-1000.0, 1000.0});
        a->Field("speed", &w.speed_m_s, {0, 20});
        a->Enum("loop", &w.loop);
        a->Field("start_delay", &w.start_delay_s, {0, 86400});
        a->Field("personal_distance", &personal_distance_m, {0, 20});
        break;
      }
      case MotionKind::kConstantVelocity: {
        auto& c = EmplaceMotion<ConstantVelocityMotion>(&motion);
        a->Field("start", &c.start_W, {-1000.0, 1000.0});
        a->Field("velocity", &c.velocity_W, {-20, 20});
        a->Field("start_time", &c.start_time_s, {0, 86400});
        break;
      }
      case MotionKind::kRandomWalk: {
        auto& r = EmplaceMotion<RandomWalkMotion>(&motion);
        a->Field("seed", &r.seed);
        a->Field("area_centre", &r.area_centre_W, {-1000.0, 1000.0});
        a->Field("area_radius", &r.area_radius_m, {0, 1000.0});
        a->Field("speed", &r.speed_m_s, {0, 20});
        a->Field("pause", &r.pause_s, {0, 3600});
        break;
      }
    }
  }

  /// One mover per kind of motion: together they reach every key of Serialize.
  static std::vector<MovingObstacle> KeyExamples() {
    std::vector<MovingObstacle> movers(3);
    movers[0].motion = WaypointMotion{};
    movers[1].motion = ConstantVelocityMotion{};
    movers[2].motion = RandomWalkMotion{};
    return movers;
  }
};

/// Checks one mover. Key paths are relative to the mover, with the field names of the structs
/// above without unit suffixes: name, half_height, radius, box_half_extents[i], rgba[i], and for
/// the motions waypoints, waypoints[j], speed, start_delay, start, velocity, start_time,
/// area_centre, area_radius, pause[i].
/// @throws common::InputError naming the key path and the value.
void ValidateMovingObstacle(const MovingObstacle& mover);

/// Checks every mover (`[i].<field>`, see ValidateMovingObstacle) and that their names are unique.
/// @throws common::InputError naming the key path and the value.
void ValidateMovingObstacles(const std::vector<MovingObstacle>& movers);

/// The mover's shape in its own frame O (X_WO of the result is the identity), with sizes in the
/// conventions of common::Primitive (a capsule's size is its radius and the half-length of its
/// cylinder part).
common::Primitive MoverPrimitive(const MovingObstacle& mover);

/// Radius of the disc about O's origin that bounds the mover's planar footprint [m] (planners
/// treat a mover as this disc).
double MoverFootprintRadius(const MovingObstacle& mover);

/// Planar state of a mover at one time, in W.
struct MoverPlanarState {
  Eigen::Vector2d p_W{Eigen::Vector2d::Zero()};  ///< position of O's origin [m]
  Eigen::Vector2d v_W{Eigen::Vector2d::Zero()};  ///< velocity [m/s], zero while it stands
  double yaw{0.0};  ///< heading [rad]: the direction of its current or last motion (while it
                    ///< stands before moving: of its first motion; 0 if it never moves)
};

/// Pose of the mover's frame O in W for a planar state: upright, on the ground (the world's ground
/// height at p_W plus the half height), turned to the state's yaw.
Eigen::Isometry3d MoverPose(const MovingObstacle& mover, const MoverPlanarState& state,
                            const TerrainWorld& world);

/// The motion of one mover over time as straight legs (walks and pauses), for repeated queries.
/// Waypoint and constant-velocity motions are built at construction; a random walker's legs are
/// drawn lazily as later times are asked for. The state at time t depends only on the mover and
/// t, never on earlier queries, and is bit-identical between tracks of the same mover. Times before
/// 0 give the state at 0.
class MoverTrack {
 public:
  /// @throws common::InputError if the mover is invalid (ValidateMovingObstacle).
  explicit MoverTrack(MovingObstacle mover);

  const MovingObstacle& mover() const { return mover_; }

  /// Planar state at time t_s [s], which must be finite (std::invalid_argument otherwise). Not
  /// const: a random walker may draw further legs (amortised; no allocation once drawn).
  MoverPlanarState PlanarStateAt(double t_s);

  /// MoverPose of the planar state at t_s.
  Eigen::Isometry3d PoseAt(double t_s, const TerrainWorld& world);

 private:
  // A straight leg from p0 (at t0) to p1 (at t1) at constant velocity v; a pause has v = 0.
  struct Leg {
    double t0_s{0.0};
    double t1_s{0.0};
    Eigen::Vector2d p0_W{Eigen::Vector2d::Zero()};
    Eigen::Vector2d p1_W{Eigen::Vector2d::Zero()};
    Eigen::Vector2d v_W{Eigen::Vector2d::Zero()};
    double yaw{0.0};
  };
  void AppendWalk(const Eigen::Vector2d& to_W, double speed_m_s);
  void AppendPause(double duration_s);
  void AppendRandomLegs();

  MovingObstacle mover_;
  std::vector<Leg> legs_;  // consecutive: legs_[k + 1].t0_s == legs_[k].t1_s
  double period_s_{0.0};   // > 0: looping waypoints repeat every period_s_ after legs_[0].t0_s
  std::optional<common::Random> random_;  // a random walker's draws, positioned after legs_
};

/// Pose of the mover's frame O in W at time t_s [s] (builds a MoverTrack: for repeated queries of
/// a random walker keep a MoverTrack instead). @throws common::InputError for an invalid mover.
Eigen::Isometry3d MoverPoseAt(const MovingObstacle& mover, double t_s, const TerrainWorld& world);

/// Planar velocity of the mover in W at time t_s [m/s] (ground truth for predictions).
/// @throws common::InputError for an invalid mover.
Eigen::Vector2d MoverVelocityAt(const MovingObstacle& mover, double t_s);

}  // namespace trav::sim
