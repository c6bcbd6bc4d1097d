#include "scenarios/run/end_conditions.h"

#include <cmath>

namespace trav::scenarios {

std::string CollisionCause(const Eigen::Vector2d& robot_W, const Eigen::Vector2d& v_robot_W,
                           const Eigen::Vector2d& mover_W, const Eigen::Vector2d& v_mover_W) {
  constexpr double kStopped_m_s = 0.05;
  const Eigen::Vector2d towards_mover = (mover_W - robot_W).normalized();
  const double robot_approach = v_robot_W.dot(towards_mover);
  const double mover_approach = -v_mover_W.dot(towards_mover);
  return v_robot_W.norm() > kStopped_m_s && robot_approach >= mover_approach ? "robot" : "mover";
}

RolloverCondition::RolloverCondition(double limit_deg) : limit_rad_(limit_deg / (180.0 / M_PI)) {}

std::optional<Outcome> RolloverCondition::Check(const ClosedLoop& /*loop*/, const LoopStep& step) {
  if (common::TiltAngle(step.state.X_WB.linear()) > limit_rad_) return Outcome::kRolledOver;
  return std::nullopt;
}

std::optional<Outcome> CollisionCondition::Check(const ClosedLoop& loop, const LoopStep& step) {
  const sim::Simulation& simulation = loop.simulation();
  simulation.RobotContacts(&contacts_);
  const auto collision =
      std::find_if(contacts_.begin(), contacts_.end(),
                   [](const sim::RobotContact& c) { return sim::IsCollision(c); });
  if (collision == contacts_.end()) return std::nullopt;
  const common::RobotState& state = step.state;
  CollisionRecord record{std::string(collision->target_name),
                         collision->target == sim::ContactTarget::kMover,
                         collision->relative_speed_m_s, state.time_s};
  const Eigen::Vector2d v_robot_W = (state.X_WB.linear() * state.v_WB_B).head<2>();
  record.robot_speed_m_s = v_robot_W.norm();
  if (record.mover) {
    record.caused_by =
        CollisionCause(state.X_WB.translation().head<2>(), v_robot_W,
                       simulation.MoverPose(collision->target_index).translation().head<2>(),
                       simulation.MoverVelocity(collision->target_index));
  }
  record_ = record;
  return Outcome::kCollision;
}

std::optional<Outcome> GoalCondition::Check(const ClosedLoop& /*loop*/, const LoopStep& step) {
  if ((step.state.X_WB.translation().head<2>() - goal_W_).norm() > radius_m_) return std::nullopt;
  time_to_goal_s_ = step.state.time_s;
  return Outcome::kSuccess;
}

std::optional<Outcome> StuckCondition::Check(const ClosedLoop& /*loop*/, const LoopStep& step) {
  if (monitor_.Update(step.state.time_s, step.state.X_WB.translation().head<2>())) {
    return Outcome::kStuck;
  }
  return std::nullopt;
}

std::optional<Outcome> PlanningFailureCondition::Check(const ClosedLoop& loop,
                                                       const LoopStep& step) {
  if (loop.navigator() == nullptr) return std::nullopt;
  if (loop.navigator()->time_without_plan_s(step.state.time_s) > limit_s_) {
    cause_ = "no_plan";
    return Outcome::kPlanningFailure;
  }
  movers_W_.clear();
  for (const planner::MovingObstacle& mover : loop.true_movers()) {
    movers_W_.push_back(mover.PositionAt(step.state.time_s));
  }
  if (livelock_.Update(step.state.time_s, step.state.X_WB.translation().head<2>(), movers_W_)) {
    cause_ = "livelock";
    return Outcome::kPlanningFailure;
  }
  return std::nullopt;
}

std::optional<Outcome> TimeoutCondition::Check(const ClosedLoop& /*loop*/, const LoopStep& step) {
  if (step.last) return Outcome::kTimeout;
  return std::nullopt;
}

}  // namespace trav::scenarios
