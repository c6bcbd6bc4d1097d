#include "sim/moving_obstacles.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"

namespace trav::sim {
namespace {

using ::testing::HasSubstr;

MovingObstacle Walker(WaypointMotion motion) {
  MovingObstacle mover;
  mover.name = "walker";
  mover.motion = std::move(motion);
  return mover;
}

// Checks the planar state at `t_s` exactly.
void ExpectState(MoverTrack* track, double t_s, const Eigen::Vector2d& p_W,
                 const Eigen::Vector2d& v_W, double yaw) {
  const MoverPlanarState state = track->PlanarStateAt(t_s);
  EXPECT_EQ(state.p_W, p_W) << "t = " << t_s << ": at " << state.p_W.transpose();
  EXPECT_EQ(state.v_W, v_W) << "t = " << t_s << ": moving at " << state.v_W.transpose();
  EXPECT_EQ(state.yaw, yaw) << "t = " << t_s;
}

TEST(MoverTrackTest, WaypointsAreWalkedAtTheirSpeedAfterTheDelayAndTheMoverStopsAtTheEnd) {
  MoverTrack dut(Walker({{{0, 0}, {4, 0}, {4, 2}}, 2.0, WaypointLoop::kNone, 1.0}));
  // standing at the first waypoint, facing the first leg, until the delay ends
  ExpectState(&dut, 0.0, {0, 0}, {0, 0}, 0.0);
  ExpectState(&dut, 0.5, {0, 0}, {0, 0}, 0.0);
  ExpectState(&dut, 1.0, {0, 0}, {2, 0}, 0.0);
  ExpectState(&dut, 2.0, {2, 0}, {2, 0}, 0.0);
  ExpectState(&dut, 3.0, {4, 0}, {0, 2}, M_PI / 2);
  ExpectState(&dut, 3.5, {4, 1}, {0, 2}, M_PI / 2);
  ExpectState(&dut, 4.0, {4, 2}, {0, 0}, M_PI / 2);
  ExpectState(&dut, 100.0, {4, 2}, {0, 0}, M_PI / 2);
}

TEST(MoverTrackTest, CyclingWaypointsReturnToTheFirstAndRepeat) {
  // a 4 x 2 m rectangle at 2 m/s: legs of 2, 1, 2 and 1 s, a period of 6 s
  MoverTrack dut(Walker({{{0, 0}, {4, 0}, {4, 2}, {0, 2}}, 2.0, WaypointLoop::kCycle, 0.0}));
  ExpectState(&dut, 1.0, {2, 0}, {2, 0}, 0.0);
  ExpectState(&dut, 5.5, {0, 1}, {0, -2}, -M_PI / 2);
  ExpectState(&dut, 7.0, {2, 0}, {2, 0}, 0.0);
  ExpectState(&dut, 9.5, {3, 2}, {-2, 0}, M_PI);
  ExpectState(&dut, 6.0 * 100 + 3.5, {3, 2}, {-2, 0}, M_PI);
}

TEST(MoverTrackTest, PingPongWaypointsTurnBackAtEachEnd) {
  MoverTrack dut(Walker({{{0, 0}, {4, 0}}, 2.0, WaypointLoop::kPingPong, 0.5}));
  ExpectState(&dut, 1.5, {2, 0}, {2, 0}, 0.0);
  ExpectState(&dut, 3.5, {2, 0}, {-2, 0}, M_PI);
  ExpectState(&dut, 5.5, {2, 0}, {2, 0}, 0.0);
  ExpectState(&dut, 7.5, {2, 0}, {-2, 0}, M_PI);
}

TEST(MoverTrackTest, OneWaypointStandsStill) {
  MoverTrack dut(Walker({{{3, -1}, {3, -1}}, 1.0, WaypointLoop::kCycle, 0.0}));
  ExpectState(&dut, 0.0, {3, -1}, {0, 0}, 0.0);
  ExpectState(&dut, 50.0, {3, -1}, {0, 0}, 0.0);
}

TEST(MoverTrackTest, ConstantVelocityCrosserWaitsForItsStartTime) {
  MovingObstacle mover;
  mover.name = "crosser";
  mover.motion = ConstantVelocityMotion{{1, 2}, {0.5, -1}, 2.0};
  MoverTrack dut(mover);
  const double yaw = std::atan2(-1.0, 0.5);
  ExpectState(&dut, 1.0, {1, 2}, {0, 0}, yaw);
  ExpectState(&dut, 2.0, {1, 2}, {0.5, -1}, yaw);
  ExpectState(&dut, 4.0, {2, 0}, {0.5, -1}, yaw);
  EXPECT_EQ(MoverVelocityAt(mover, 4.0), Eigen::Vector2d(0.5, -1));
  EXPECT_THROW(dut.PlanarStateAt(std::nan("")), std::invalid_argument);
}

MovingObstacle RandomWalker(std::uint64_t seed) {
  MovingObstacle mover;
  mover.name = "wanderer";
  RandomWalkMotion walk;
  walk.seed = seed;
  walk.area_centre_W = {3, -1};
  walk.area_radius_m = 2.0;
  walk.speed_m_s = 1.5;
  walk.pause_s = {0.5, 1.0};
  mover.motion = walk;
  return mover;
}

TEST(MoverTrackTest, RandomWalkerStaysInItsDiscWalksAtItsSpeedAndPauses) {
  MoverTrack dut(RandomWalker(7));
  int paused = 0;
  double farthest = 0.0;
  const int samples = 6000;
  for (int k = 0; k <= samples; ++k) {
    const MoverPlanarState state = dut.PlanarStateAt(0.05 * k);
    const double distance = (state.p_W - Eigen::Vector2d(3, -1)).norm();
    ASSERT_LE(distance, 2.0 + 1e-12) << "t = " << 0.05 * k;
    farthest = std::max(farthest, distance);
    if (state.v_W.isZero(0.0)) {
      ++paused;
    } else {
      ASSERT_NEAR(state.v_W.norm(), 1.5, 1e-12);
      ASSERT_NEAR(state.yaw, std::atan2(state.v_W.y(), state.v_W.x()), 1e-12);
    }
  }
  // legs average about 1.8 m (1.2 s) and pauses 0.75 s: roughly 40 % of the time paused
  EXPECT_GT(paused, samples / 5);
  EXPECT_LT(paused, samples * 3 / 5);
  EXPECT_GT(farthest, 1.8);
}

TEST(MoverTrackTest, RandomWalkerIsAPureFunctionOfSeedAndTime) {
  MoverTrack forward(RandomWalker(7));
  MoverTrack backward(RandomWalker(7));
  MoverTrack other(RandomWalker(8));
  std::vector<Eigen::Vector2d> positions;
  for (int k = 0; k <= 1000; ++k) positions.push_back(forward.PlanarStateAt(0.1 * k).p_W);
  // queried in reverse order (the first query draws every leg at once), by a fresh track per query,
  // and with another seed
  int differ = 0;
  const TerrainWorld world = [] {
    TerrainConfig config;
    config.type = TerrainType::kFlat;
    config.size_m = {10, 10};
    return GenerateTerrain(config);
  }();
  for (int k = 1000; k >= 0; --k) {
    const MoverPlanarState state = backward.PlanarStateAt(0.1 * k);
    ASSERT_EQ(state.p_W, positions[static_cast<std::size_t>(k)]) << "t = " << 0.1 * k;
    if (k % 100 == 0) {
      EXPECT_EQ(MoverPoseAt(RandomWalker(7), 0.1 * k, world).translation().head<2>(),
                positions[static_cast<std::size_t>(k)]);
    }
    if (other.PlanarStateAt(0.1 * k).p_W != state.p_W) ++differ;
  }
  EXPECT_GT(differ, 990);
}

TEST(MoverPoseTest, StandsUprightOnTheGroundFacingItsMotion) {
  TerrainConfig config;
  config.type = TerrainType::kSlope;
  config.size_m = {20, 10};
  config.slope.start_x_m = 0.0;
  const TerrainWorld world = GenerateTerrain(config);
  MovingObstacle mover;
  mover.name = "pedestrian";
  mover.motion = ConstantVelocityMotion{{-2, 1}, {1, 0.5}, 0.0};
  const Eigen::Isometry3d X_WO = MoverPoseAt(mover, 4.0, world);
  EXPECT_EQ(X_WO.translation().head<2>(), Eigen::Vector2d(2, 3));
  EXPECT_EQ(X_WO.translation().z(), world.GroundHeight({2, 3}) + 0.85);
  EXPECT_GT(X_WO.translation().z(), 0.85 + 0.5);  // on the ramp
  EXPECT_TRUE(X_WO.linear().isApprox(
      Eigen::AngleAxisd(std::atan2(0.5, 1.0), Eigen::Vector3d::UnitZ()).toRotationMatrix(), 1e-15));
}

TEST(MoverShapeTest, PrimitivesAndFootprints) {
  MovingObstacle pedestrian;
  const common::Primitive capsule = MoverPrimitive(pedestrian);
  EXPECT_EQ(capsule.shape, common::ShapeType::kCapsule);
  EXPECT_EQ(capsule.size, Eigen::Vector3d(0.25, 0.6, 0.0));  // 0.25 + 0.6 + 0.25 = 0.85 * 2
  EXPECT_EQ(MoverFootprintRadius(pedestrian), 0.25);

  MovingObstacle cart;
  cart.shape = MoverShape::kBox;
  cart.box_half_extents_m = {0.3, 0.4};
  cart.half_height_m = 0.5;
  EXPECT_EQ(MoverPrimitive(cart).size, Eigen::Vector3d(0.3, 0.4, 0.5));
  EXPECT_DOUBLE_EQ(MoverFootprintRadius(cart), 0.5);

  MovingObstacle drum;
  drum.shape = MoverShape::kCylinder;
  drum.radius_m = 0.3;
  drum.half_height_m = 0.45;
  EXPECT_EQ(MoverPrimitive(drum).shape, common::ShapeType::kCylinder);
  EXPECT_EQ(MoverPrimitive(drum).size, Eigen::Vector3d(0.3, 0.45, 0.0));
}

// The message of the InputError that validating `movers` throws ("" if none).
std::string ValidationError(const std::vector<MovingObstacle>& movers) {
  try {
    ValidateMovingObstacles(movers);
  } catch (const common::InputError& error) {
    return error.what();
  }
  return "";
}

TEST(MoverValidationTest, ValidMoversPass) {
  MovingObstacle a = Walker({{{0, 0}, {1, 0}}, 1.0, WaypointLoop::kPingPong, 0.0});
  MovingObstacle b = RandomWalker(1);
  MovingObstacle c;
  c.name = "crosser-2";
  EXPECT_EQ(ValidationError({a, b, c}), "");
}

TEST(MoverValidationTest, BadParametersNameTheKeyPathAndTheValue) {
  const MovingObstacle good = Walker({{{0, 0}, {1, 0}}, 1.0, WaypointLoop::kNone, 0.0});
  auto error_with = [&](auto change) {
    MovingObstacle first = good;
    first.name = "first";
    MovingObstacle second = good;
    second.name = "second";
    change(&second);
    return ValidationError({first, second});
  };
  EXPECT_EQ(
      error_with([](MovingObstacle* m) { std::get<WaypointMotion>(m->motion).speed_m_s = -1.0; }),
      "[1].speed: value -1.000000 must be > 0 and finite");
  EXPECT_EQ(error_with(
                [](MovingObstacle* m) { std::get<WaypointMotion>(m->motion).waypoints_W.clear(); }),
            "[1].waypoints: is empty: at least one point is required");
  EXPECT_THAT(error_with([](MovingObstacle* m) {
                std::get<WaypointMotion>(m->motion).waypoints_W[1].y() = INFINITY;
              }),
              HasSubstr("[1].waypoints[1][1]: value inf must be finite"));
  EXPECT_THAT(error_with([](MovingObstacle* m) {
                std::get<WaypointMotion>(m->motion).start_delay_s = -2.0;
              }),
              HasSubstr("[1].start_delay: value -2.000000"));
  EXPECT_THAT(error_with([](MovingObstacle* m) {
                m->shape = MoverShape::kBox;
                m->box_half_extents_m.y() = 0.0;
              }),
              HasSubstr("[1].box_half_extents[1]: value 0.000000 must be > 0"));
  EXPECT_THAT(error_with([](MovingObstacle* m) {
                m->shape = MoverShape::kCylinder;
                m->radius_m = -0.1;
              }),
              HasSubstr("[1].radius: value -0.100000"));
  EXPECT_THAT(error_with([](MovingObstacle* m) { m->half_height_m = 0.2; }),
              HasSubstr("[1].half_height: value 0.200000 must be > the radius "
                        "(0.250000) for a capsule"));
  EXPECT_THAT(error_with([](MovingObstacle* m) { m->rgba[3] = 1.5f; }),
              HasSubstr("[1].rgba[3]: value 1.500000 must be in [0, 1]"));
  EXPECT_THAT(error_with([](MovingObstacle* m) {
                m->motion = ConstantVelocityMotion{{0, 0}, {NAN, 0}, 0.0};
              }),
              HasSubstr("[1].velocity[0]: value nan must be finite"));
  EXPECT_THAT(error_with([](MovingObstacle* m) {
                m->motion = ConstantVelocityMotion{{0, 0}, {1, 0}, -1.0};
              }),
              HasSubstr("[1].start_time: value -1.000000"));
  EXPECT_THAT(error_with([](MovingObstacle* m) {
                RandomWalkMotion walk;
                walk.area_radius_m = 0.0;
                m->motion = walk;
              }),
              HasSubstr("[1].area_radius: value 0.000000 must be > 0"));
  EXPECT_THAT(error_with([](MovingObstacle* m) {
                RandomWalkMotion walk;
                walk.pause_s = {2.0, 1.0};
                m->motion = walk;
              }),
              HasSubstr("[1].pause[1]: value 1.000000 must be finite and >= "
                        "pause[0]"));
  EXPECT_EQ(error_with([](MovingObstacle* m) { m->name = "a b"; }),
            "[1].name: 'a b' must be non-empty and use only letters, digits, '_' "
            "and '-'");
  EXPECT_EQ(error_with([](MovingObstacle* m) { m->name = "first"; }),
            "[1].name: 'first' is already the name of item 0");
}

TEST(MoverValidationTest, ATrackRejectsAnInvalidMover) {
  MovingObstacle mover = RandomWalker(1);
  std::get<RandomWalkMotion>(mover.motion).speed_m_s = 0.0;
  EXPECT_THROW(MoverTrack{mover}, common::InputError);
}

}  // namespace
}  // namespace trav::sim
