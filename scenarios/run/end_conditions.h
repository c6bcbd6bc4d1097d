#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "scenarios/run/closed_loop.h"
#include "scenarios/run/run_metrics.h"

namespace trav::scenarios {

/// The contact that ended a run as a collision.
struct CollisionRecord {
  std::string target;              ///< the obstacle's or mover's name
  bool mover{false};               ///< a moving obstacle
  double relative_speed_m_s{0.0};  ///< planar speed of the base relative to the mover
  double time_s{0.0};
  double robot_speed_m_s{0.0};  ///< planar speed of the base at contact
  /// Who closed the gap: "robot" (a static obstacle, or the robot approached the mover at least
  /// as fast as the mover approached it), or "mover" (a mover ran into a robot that was stopped
  /// or slower to approach).
  std::string caused_by{"robot"};
};

/// Who closed the gap at a contact: "robot" if it approached the mover at least as fast as the
/// mover approached it (and was moving), else "mover".
std::string CollisionCause(const Eigen::Vector2d& robot_W, const Eigen::Vector2d& v_robot_W,
                           const Eigen::Vector2d& mover_W, const Eigen::Vector2d& v_mover_W);

/// Rolled over: the base tilted beyond the limit.
class RolloverCondition : public EndCondition {
 public:
  explicit RolloverCondition(double limit_deg);
  Stage stage() const override { return Stage::kPhysical; }
  std::optional<Outcome> Check(const ClosedLoop& loop, const LoopStep& step) override;

 private:
  double limit_rad_;
};

/// Collision: the robot touched an obstacle or a mover (wheels on the ground do not count).
class CollisionCondition : public EndCondition {
 public:
  Stage stage() const override { return Stage::kPhysical; }
  std::optional<Outcome> Check(const ClosedLoop& loop, const LoopStep& step) override;

  /// The contact that ended the run, if one did.
  const std::optional<CollisionRecord>& record() const { return record_; }

 private:
  std::vector<sim::RobotContact> contacts_;
  std::optional<CollisionRecord> record_;
};

/// Success: the base within the goal radius of the goal.
class GoalCondition : public EndCondition {
 public:
  GoalCondition(const Eigen::Vector2d& goal_W, double radius_m)
      : goal_W_(goal_W), radius_m_(radius_m) {}
  Stage stage() const override { return Stage::kMission; }
  std::optional<Outcome> Check(const ClosedLoop& loop, const LoopStep& step) override;

  /// Simulation time at which the goal was reached (0: not reached).
  double time_to_goal_s() const { return time_to_goal_s_; }

 private:
  Eigen::Vector2d goal_W_;
  double radius_m_;
  double time_to_goal_s_{0.0};
};

/// Stuck: no progress (ProgressMonitor) for the scenario's stuck time.
class StuckCondition : public EndCondition {
 public:
  StuckCondition(double window_s, double distance_m) : monitor_(window_s, distance_m) {}
  Stage stage() const override { return Stage::kMission; }
  std::optional<Outcome> Check(const ClosedLoop& loop, const LoopStep& step) override;

 private:
  ProgressMonitor monitor_;
};

/// Planning failure: the navigator has had no valid plan for longer than the limit, or it has
/// plans but the robot gets nowhere with them (LivelockMonitor).
class PlanningFailureCondition : public EndCondition {
 public:
  PlanningFailureCondition(double limit_s, double livelock_time_s, double livelock_radius_m)
      : limit_s_(limit_s), livelock_(livelock_time_s, livelock_radius_m) {}
  Stage stage() const override { return Stage::kMission; }
  std::optional<Outcome> Check(const ClosedLoop& loop, const LoopStep& step) override;

  /// Why the run failed: "no_plan" (no valid plan for the limit), "livelock" (plans, no progress);
  /// empty while it has not.
  const std::string& cause() const { return cause_; }

 private:
  double limit_s_;
  LivelockMonitor livelock_;
  std::string cause_;
  std::vector<Eigen::Vector2d> movers_W_;  // the movers' positions this step
};

/// Timeout: the scenario's duration ran out before the goal.
class TimeoutCondition : public EndCondition {
 public:
  Stage stage() const override { return Stage::kMission; }
  std::optional<Outcome> Check(const ClosedLoop& loop, const LoopStep& step) override;
};

}  // namespace trav::scenarios
