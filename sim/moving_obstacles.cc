#include "sim/moving_obstacles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/input_error.h"

namespace trav::sim {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// RequireValue for `<field>` or `<field>[<index>]` (index >= 0); the key is composed only on
// failure (every MoverTrack validates its mover).
void Require(bool condition, const char* field, int index, double value, const char* expectation) {
  if (condition) return;
  std::string key = field;
  if (index >= 0) key += "[" + std::to_string(index) + "]";
  common::RequireValue(false, key, value, expectation);
}

void Require(bool condition, const char* field, double value, const char* expectation) {
  Require(condition, field, -1, value, expectation);
}

void RequireFinite(const Eigen::Vector2d& v, const char* field) {
  for (int i = 0; i < 2; ++i) Require(std::isfinite(v[i]), field, i, v[i], "must be finite");
}

bool IsValidName(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

void ValidateMotion(const WaypointMotion& motion) {
  if (motion.waypoints_W.empty()) {
    throw common::InputError("", "waypoints", "is empty: at least one point is required");
  }
  for (std::size_t j = 0; j < motion.waypoints_W.size(); ++j) {
    const Eigen::Vector2d& p = motion.waypoints_W[j];
    if (!p.allFinite()) RequireFinite(p, ("waypoints[" + std::to_string(j) + "]").c_str());
  }
  Require(motion.speed_m_s > 0.0 && std::isfinite(motion.speed_m_s), "speed", motion.speed_m_s,
          "must be > 0 and finite");
  Require(motion.start_delay_s >= 0.0 && std::isfinite(motion.start_delay_s), "start_delay",
          motion.start_delay_s, "must be >= 0 and finite");
}

void ValidateMotion(const ConstantVelocityMotion& motion) {
  RequireFinite(motion.start_W, "start");
  RequireFinite(motion.velocity_W, "velocity");
  Require(motion.start_time_s >= 0.0 && std::isfinite(motion.start_time_s), "start_time",
          motion.start_time_s, "must be >= 0 and finite");
}

void ValidateMotion(const RandomWalkMotion& motion) {
  RequireFinite(motion.area_centre_W, "area_centre");
  Require(motion.area_radius_m > 0.0 && std::isfinite(motion.area_radius_m), "area_radius",
          motion.area_radius_m, "must be > 0 and finite");
  Require(motion.speed_m_s > 0.0 && std::isfinite(motion.speed_m_s), "speed", motion.speed_m_s,
          "must be > 0 and finite");
  Require(motion.pause_s[0] >= 0.0, "pause[0]", motion.pause_s[0], "must be >= 0");
  Require(motion.pause_s[1] >= motion.pause_s[0] && std::isfinite(motion.pause_s[1]), "pause[1]",
          motion.pause_s[1], "must be finite and >= pause[0]");
}

double Heading(const Eigen::Vector2d& direction) {
  return std::atan2(direction.y(), direction.x());
}

}  // namespace

void ValidateMovingObstacle(const MovingObstacle& mover) {
  if (mover.personal_distance_m < 0.0 ||
      (mover.personal_distance_m > 0.0 && !std::holds_alternative<WaypointMotion>(mover.motion))) {
    throw common::InputError("", "personal_distance",
                             "value " + std::to_string(mover.personal_distance_m) +
                                 " must be >= 0, and > 0 only with motion waypoints");
  }
  if (!IsValidName(mover.name)) {
    throw common::InputError(
        "", "name",
        "'" + mover.name + "' must be non-empty and use only letters, digits, '_' and '-'");
  }
  Require(mover.half_height_m > 0.0 && std::isfinite(mover.half_height_m), "half_height",
          mover.half_height_m, "must be > 0 and finite");
  switch (mover.shape) {
    case MoverShape::kBox:
      for (int i = 0; i < 2; ++i) {
        Require(mover.box_half_extents_m[i] > 0.0 && std::isfinite(mover.box_half_extents_m[i]),
                "box_half_extents", i, mover.box_half_extents_m[i], "must be > 0 and finite");
      }
      break;
    case MoverShape::kCylinder:
      Require(mover.radius_m > 0.0 && std::isfinite(mover.radius_m), "radius", mover.radius_m,
              "must be > 0 and finite");
      break;
    case MoverShape::kCapsule:
      Require(mover.radius_m > 0.0 && std::isfinite(mover.radius_m), "radius", mover.radius_m,
              "must be > 0 and finite");
      if (mover.half_height_m <= mover.radius_m) {
        const std::string expectation =
            "must be > the radius (" + std::to_string(mover.radius_m) + ") for a capsule";
        Require(false, "half_height", mover.half_height_m, expectation.c_str());
      }
      break;
  }
  for (int i = 0; i < 4; ++i) {
    Require(mover.rgba[i] >= 0.0f && mover.rgba[i] <= 1.0f, "rgba", i, mover.rgba[i],
            "must be in [0, 1]");
  }
  std::visit([&](const auto& motion) { ValidateMotion(motion); }, mover.motion);
}

void ValidateMovingObstacles(const std::vector<MovingObstacle>& movers) {
  for (std::size_t i = 0; i < movers.size(); ++i) {
    common::ValidateAt("[" + std::to_string(i) + "]", [&] {
      ValidateMovingObstacle(movers[i]);
      for (std::size_t j = 0; j < i; ++j) {
        if (movers[j].name == movers[i].name) {
          throw common::InputError(
              "", "name",
              "'" + movers[i].name + "' is already the name of item " + std::to_string(j));
        }
      }
    });
  }
}

common::Primitive MoverPrimitive(const MovingObstacle& mover) {
  common::Primitive primitive;
  switch (mover.shape) {
    case MoverShape::kBox:
      primitive.shape = common::ShapeType::kBox;
      primitive.size = Eigen::Vector3d(mover.box_half_extents_m.x(), mover.box_half_extents_m.y(),
                                       mover.half_height_m);
      break;
    case MoverShape::kCylinder:
      primitive.shape = common::ShapeType::kCylinder;
      primitive.size = Eigen::Vector3d(mover.radius_m, mover.half_height_m, 0.0);
      break;
    case MoverShape::kCapsule:
      primitive.shape = common::ShapeType::kCapsule;
      primitive.size = Eigen::Vector3d(mover.radius_m, mover.half_height_m - mover.radius_m, 0.0);
      break;
  }
  return primitive;
}

double MoverFootprintRadius(const MovingObstacle& mover) {
  return mover.shape == MoverShape::kBox ? mover.box_half_extents_m.norm() : mover.radius_m;
}

Eigen::Isometry3d MoverPose(const MovingObstacle& mover, const MoverPlanarState& state,
                            const TerrainWorld& world) {
  Eigen::Isometry3d X_WO = Eigen::Isometry3d::Identity();
  X_WO.linear() = Eigen::AngleAxisd(state.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X_WO.translation() = Eigen::Vector3d(state.p_W.x(), state.p_W.y(),
                                       world.GroundHeight(state.p_W) + mover.half_height_m);
  return X_WO;
}

MoverTrack::MoverTrack(MovingObstacle mover) : mover_(std::move(mover)) {
  ValidateMovingObstacle(mover_);
  if (const auto* waypoints = std::get_if<WaypointMotion>(&mover_.motion)) {
    std::vector<Eigen::Vector2d> path = waypoints->waypoints_W;
    if (waypoints->loop == WaypointLoop::kCycle) {
      path.push_back(path.front());
    } else if (waypoints->loop == WaypointLoop::kPingPong) {
      path.insert(path.end(), waypoints->waypoints_W.rbegin() + 1, waypoints->waypoints_W.rend());
    }
    // a zero-length leg ending at the first waypoint holds the mover there until the delay ends
    legs_.push_back(Leg{waypoints->start_delay_s, waypoints->start_delay_s, path.front(),
                        path.front(), Eigen::Vector2d::Zero(), 0.0});
    for (std::size_t k = 1; k < path.size(); ++k) AppendWalk(path[k], waypoints->speed_m_s);
    if (legs_.size() > 1) {
      legs_.front().yaw = legs_[1].yaw;
      if (waypoints->loop != WaypointLoop::kNone) {
        period_s_ = legs_.back().t1_s - legs_.front().t0_s;
      }
    }
  } else if (const auto* crosser = std::get_if<ConstantVelocityMotion>(&mover_.motion)) {
    const bool moves = !crosser->velocity_W.isZero(0.0);
    legs_.push_back(Leg{crosser->start_time_s, kInfinity, crosser->start_W, crosser->start_W,
                        crosser->velocity_W, moves ? Heading(crosser->velocity_W) : 0.0});
  } else {
    const auto& walker = std::get<RandomWalkMotion>(mover_.motion);
    random_.emplace(walker.seed);
    const double radius = walker.area_radius_m * std::sqrt(random_->Uniform());
    const double angle = 2.0 * M_PI * random_->Uniform();
    const Eigen::Vector2d start_W =
        walker.area_centre_W + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    // the anchor leg is never returned (times are clamped to >= 0 and the first walk starts at 0)
    legs_.push_back(Leg{0.0, 0.0, start_W, start_W, Eigen::Vector2d::Zero(), 0.0});
  }
}

void MoverTrack::AppendWalk(const Eigen::Vector2d& to_W, double speed_m_s) {
  const Leg& last = legs_.back();
  const Eigen::Vector2d delta = to_W - last.p1_W;
  const double length = delta.norm();
  if (length == 0.0) return;
  legs_.push_back(Leg{last.t1_s, last.t1_s + length / speed_m_s, last.p1_W, to_W,
                      delta / length * speed_m_s, Heading(delta)});
}

void MoverTrack::AppendPause(double duration_s) {
  if (duration_s <= 0.0) return;
  const Leg& last = legs_.back();
  legs_.push_back(Leg{last.t1_s, last.t1_s + duration_s, last.p1_W, last.p1_W,
                      Eigen::Vector2d::Zero(), last.yaw});
}

void MoverTrack::AppendRandomLegs() {
  // one walk to a fresh target, then the pause there (a target at the current position adds no
  // walk, and a zero pause no leg: the next round draws again)
  const auto& walker = std::get<RandomWalkMotion>(mover_.motion);
  const double radius = walker.area_radius_m * std::sqrt(random_->Uniform());
  const double angle = 2.0 * M_PI * random_->Uniform();
  const double pause_s = random_->Uniform(walker.pause_s[0], walker.pause_s[1]);
  AppendWalk(walker.area_centre_W + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle)),
             walker.speed_m_s);
  AppendPause(pause_s);
}

MoverPlanarState MoverTrack::PlanarStateAt(double t_s) {
  if (!std::isfinite(t_s)) {
    throw std::invalid_argument("MoverTrack: time " + std::to_string(t_s) + " is not finite");
  }
  double t = std::max(t_s, 0.0);
  if (random_) {
    while (legs_.back().t1_s <= t) AppendRandomLegs();
  }
  const double t_start = legs_.front().t0_s;
  if (period_s_ > 0.0 && t > t_start) t = t_start + std::fmod(t - t_start, period_s_);

  MoverPlanarState state;
  if (t < t_start) {
    state.p_W = legs_.front().p0_W;
    state.yaw = legs_.front().yaw;
    return state;
  }
  // the last leg that has started: legs are sorted by start time
  const auto next = std::upper_bound(legs_.begin(), legs_.end(), t,
                                     [](double time, const Leg& leg) { return time < leg.t0_s; });
  const Leg& leg = *std::prev(next);
  state.yaw = leg.yaw;
  if (t >= leg.t1_s) {
    state.p_W = leg.p1_W;
  } else {
    state.p_W = leg.p0_W + (t - leg.t0_s) * leg.v_W;
    state.v_W = leg.v_W;
  }
  return state;
}

Eigen::Isometry3d MoverTrack::PoseAt(double t_s, const TerrainWorld& world) {
  return MoverPose(mover_, PlanarStateAt(t_s), world);
}

Eigen::Isometry3d MoverPoseAt(const MovingObstacle& mover, double t_s, const TerrainWorld& world) {
  return MoverTrack(mover).PoseAt(t_s, world);
}

Eigen::Vector2d MoverVelocityAt(const MovingObstacle& mover, double t_s) {
  return MoverTrack(mover).PlanarStateAt(t_s).v_W;
}

}  // namespace trav::sim
