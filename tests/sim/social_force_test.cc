#include "sim/actors/social_force.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace trav::sim {
namespace {

sim::MovingObstacle Walker(const std::string& name, Eigen::Vector2d from, Eigen::Vector2d to,
                           double personal_distance_m) {
  sim::MovingObstacle mover;  // a pedestrian capsule, radius 0.25 m
  mover.name = name;
  sim::WaypointMotion path;
  path.waypoints_W = {from, to};
  path.speed_m_s = 1.0;
  mover.motion = path;
  mover.personal_distance_m = personal_distance_m;
  return mover;
}

// Runs the crowd for `seconds` with the robot standing at robot_W (radius 0.35 m); returns the
// smallest gap between walker footprints and between a walker and the robot.
std::pair<double, double> Walk(sim::SocialForceCrowd* crowd,
                               const std::vector<sim::MovingObstacle>& movers, double seconds,
                               const Eigen::Vector2d& robot_W) {
  double walkers_gap = std::numeric_limits<double>::infinity();
  double robot_gap = std::numeric_limits<double>::infinity();
  constexpr double kDt = 0.02;
  for (double t = 0.0; t < seconds; t += kDt) {
    std::vector<Eigen::Vector2d> positions(movers.size(), Eigen::Vector2d::Zero());
    crowd->Step(t, kDt, positions, robot_W, 0.35);
    const auto& w = crowd->walkers();
    for (std::size_t i = 0; i < w.size(); ++i) {
      robot_gap = std::min(robot_gap, (w[i].p_W - robot_W).norm() - 0.25 - 0.35);
      for (std::size_t j = i + 1; j < w.size(); ++j) {
        walkers_gap = std::min(walkers_gap, (w[i].p_W - w[j].p_W).norm() - 0.5);
      }
    }
  }
  return {walkers_gap, robot_gap};
}

TEST(SocialForceTest, WalkersOnACollisionCourseKeepTheirDistanceAndStillArrive) {
  // head-on on the same line, slightly offset so that they can decide which side to pass
  const std::vector<sim::MovingObstacle> movers = {Walker("a", {-5.0, 0.0}, {5.0, 0.05}, 0.8),
                                                   Walker("b", {5.0, 0.0}, {-5.0, -0.05}, 0.8)};
  sim::SocialForceCrowd crowd(movers);
  const auto [walkers_gap, robot_gap] = Walk(&crowd, movers, 20.0, {0.0, 50.0});
  EXPECT_GT(walkers_gap, 0.4);  // never closer than half the personal distance
  EXPECT_LT((crowd.walkers()[0].p_W - Eigen::Vector2d(5.0, 0.05)).norm(), 0.5);
  EXPECT_LT((crowd.walkers()[1].p_W - Eigen::Vector2d(-5.0, -0.05)).norm(), 0.5);
  // without a personal distance they are not reactive and the crowd is empty
  EXPECT_TRUE(sim::SocialForceCrowd({Walker("c", {0, 0}, {1, 0}, 0.0)}).empty());
}

TEST(SocialForceTest, AWalkerGoesAroundAStandingRobot) {
  const std::vector<sim::MovingObstacle> movers = {Walker("a", {-5.0, 0.1}, {5.0, 0.1}, 0.6)};
  sim::SocialForceCrowd crowd(movers);
  const auto [walkers_gap, robot_gap] = Walk(&crowd, movers, 20.0, {0.0, 0.0});
  EXPECT_GT(robot_gap, 0.3);
  EXPECT_GT(crowd.walkers()[0].p_W.x(), 4.5);  // and gets past it
}

TEST(SocialForceTest, PingPongWalkersTurnBackAtTheEnds) {
  sim::MovingObstacle mover = Walker("a", {0.0, 0.0}, {2.0, 0.0}, 0.5);
  std::get<sim::WaypointMotion>(mover.motion).loop = sim::WaypointLoop::kPingPong;
  sim::SocialForceCrowd crowd({mover});
  double farthest = 0.0;
  for (double t = 0.0; t < 3.6; t += 0.02) {
    crowd.Step(t, 0.02, {Eigen::Vector2d::Zero()}, {0.0, 50.0}, 0.35);
    farthest = std::max(farthest, crowd.walkers()[0].p_W.x());
  }
  EXPECT_LT(farthest, 2.3);
  EXPECT_LT(crowd.walkers()[0].p_W.x(), 1.6);  // turned at about 2.5 s, on its way back
  EXPECT_EQ(crowd.walkers()[0].direction, -1);
}

}  // namespace
}  // namespace trav::sim
