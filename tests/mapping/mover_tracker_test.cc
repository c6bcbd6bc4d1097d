#include "mapping/mover_tracker.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace trav::mapping {
namespace {

// A frame at time t: flat ground, a static pole at (5, 5), a 6 m wall along x = -5 and a
// pedestrian (a cylinder of radius 0.25 m, 1.7 m tall) walking from (2, -3) at (0, 1) m/s.
common::PointCloud Frame(double t) {
  std::vector<Eigen::Vector3f> points;
  for (double x = -8.0; x <= 8.0; x += 0.2) {
    for (double y = -8.0; y <= 8.0; y += 0.2) {
      points.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.0f);
    }
  }
  auto cylinder = [&](const Eigen::Vector2d& c, double radius, double height) {
    for (double a = 0.0; a < 2.0 * M_PI; a += 0.3) {
      for (double z = 0.05; z <= height; z += 0.1) {
        points.emplace_back(static_cast<float>(c.x() + radius * std::cos(a)),
                            static_cast<float>(c.y() + radius * std::sin(a)),
                            static_cast<float>(z));
      }
    }
  };
  cylinder({5.0, 5.0}, 0.1, 2.0);
  cylinder(Eigen::Vector2d(2.0, -3.0) + t * Eigen::Vector2d(0.0, 1.0), 0.25, 1.7);
  for (double y = -3.0; y <= 3.0; y += 0.05) {
    for (double z = 0.05; z <= 1.5; z += 0.1) {
      points.emplace_back(-5.0f, static_cast<float>(y), static_cast<float>(z));
    }
  }
  return common::MakePointCloud(points);
}

TEST(MoverTrackerTest, RecoversAWalkersVelocityAndIgnoresStaticObjects) {
  MoverTracker dut;
  for (int k = 0; k <= 20; ++k) dut.Update(Frame(0.1 * k), Eigen::Vector3d(0, 0, 0.3), 0.1 * k);
  const std::vector<TrackedMover> movers = dut.Movers();
  ASSERT_EQ(movers.size(), 1u);
  EXPECT_NEAR(movers[0].velocity_W.x(), 0.0, 0.02);
  EXPECT_NEAR(movers[0].velocity_W.y(), 1.0, 0.02);
  EXPECT_NEAR((movers[0].position_W - Eigen::Vector2d(2.0, -1.0)).norm(), 0.0, 0.05);
  EXPECT_NEAR(movers[0].radius_m, 0.25, 0.02);
  EXPECT_EQ(movers[0].updates, 21);
  // the pole is a track but not a mover; the wall is too large to be either
  ASSERT_EQ(dut.tracks().size(), 2u);
  for (const TrackedMover& track : dut.tracks()) {
    if (track.id != movers[0].id) {
      EXPECT_NEAR((track.position_W - Eigen::Vector2d(5.0, 5.0)).norm(), 0.0, 0.01);
      EXPECT_LT(track.velocity_W.norm(), 1e-9);
    }
  }
}

TEST(MoverTrackerTest, AWalkerLeavingTheRangeIsDropped) {
  MoverTrackerConfig config;
  config.range_m = 4.0;  // the walker at (2, -3 + t) is within 4 m until t = 6.5 s
  MoverTracker dut(config);
  for (int k = 0; k <= 60; ++k) dut.Update(Frame(0.1 * k), Eigen::Vector3d(0, 0, 0.3), 0.1 * k);
  EXPECT_EQ(dut.Movers().size(), 1u);
  // its last points leave the range at t = 6.75 s; dropped 0.5 s after its last update
  for (int k = 61; k <= 76; ++k) dut.Update(Frame(0.1 * k), Eigen::Vector3d(0, 0, 0.3), 0.1 * k);
  EXPECT_TRUE(dut.Movers().empty());
}

// A trunk seen from alternating sides (its visible arc's centroid jumps 0.3 m every frame, 3 m/s
// apparently) never becomes a mover; a walker who stops after 1 s stays one.
TEST(MoverTrackerTest, AWanderingCentroidIsNotAMoverAndAPausedWalkerStaysOne) {
  auto frame = [](double t, int k) {
    std::vector<Eigen::Vector3f> points;
    for (double x = -8.0; x <= 8.0; x += 0.2) {
      for (double y = -8.0; y <= 8.0; y += 0.2)
        points.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.0f);
    }
    auto arc = [&](const Eigen::Vector2d& c, double radius, double from, double to) {
      for (double a = from; a <= to; a += 0.2) {
        for (double z = 0.05; z <= 1.7; z += 0.1) {
          points.emplace_back(static_cast<float>(c.x() + radius * std::cos(a)),
                              static_cast<float>(c.y() + radius * std::sin(a)),
                              static_cast<float>(z));
        }
      }
    };
    // the trunk at (4, 4), radius 0.3: its near or its far half, in turn
    if (k % 2 == 0) {
      arc({4.0, 4.0}, 0.3, 0.5 * M_PI, 1.5 * M_PI);
    } else {
      arc({4.0, 4.0}, 0.3, -0.5 * M_PI, 0.5 * M_PI);
    }
    // the walker: 1 m/s along +y from (-2, -3) until t = 1 s, then standing
    arc(Eigen::Vector2d(-2.0, -3.0 + std::min(t, 1.0)), 0.25, 0.0, 2.0 * M_PI);
    return common::MakePointCloud(points);
  };
  MoverTracker dut;
  for (int k = 0; k <= 30; ++k) {
    dut.Update(frame(0.1 * k, k), Eigen::Vector3d(0, 0, 0.3), 0.1 * k);
    for (const TrackedMover& mover : dut.Movers()) {
      ASSERT_LT(mover.position_W.x(), 0.0) << "the trunk reported as a mover at t = " << 0.1 * k;
    }
  }
  // 2 s after the walker stopped: still the one mover, at rest where it stopped
  const std::vector<TrackedMover> movers = dut.Movers();
  ASSERT_EQ(movers.size(), 1u);
  EXPECT_NEAR((movers[0].position_W - Eigen::Vector2d(-2.0, -2.0)).norm(), 0.0, 0.05);
  EXPECT_LT(movers[0].velocity_W.norm(), 0.05);
  // the trunk is tracked, apparently fast, but not reported
  bool trunk_tracked = false;
  for (const TrackedMover& track : dut.tracks()) {
    if ((track.position_W - Eigen::Vector2d(4.0, 4.0)).norm() < 0.3) trunk_tracked = true;
  }
  EXPECT_TRUE(trunk_tracked);
}

}  // namespace
}  // namespace trav::mapping
