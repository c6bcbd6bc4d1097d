#include "planner/trajectory_cost.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "common/footprint.h"
#include "common/random.h"

namespace trav::planner {
namespace {

// 12 x 8 m at 0.1 m: smooth costs and roughness, and a lethal disc of radius 0.6 m at (2, 0.9).
common::GridLayers TestMap() {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d(2, 0), Eigen::Vector2d(12, 8), 0.1),
      {"traversability", "roughness", "elevation"});
  const common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      const bool lethal = (p - Eigen::Vector2d(2, 0.9)).norm() < 0.6;
      map.Layer("traversability")(ix, iy) =
          lethal ? 1.0f
                 : static_cast<float>(0.3 + 0.2 * std::sin(0.9 * p.x()) * std::cos(0.7 * p.y()));
      map.Layer("roughness")(ix, iy) =
          static_cast<float>(0.02 + 0.015 * std::sin(1.3 * p.x()) * std::cos(0.9 * p.y()));
      map.Layer("elevation")(ix, iy) =
          static_cast<float>(0.8 * std::sin(0.7 * p.x()) * std::cos(0.5 * p.y()));
    }
  }
  return map;
}

// Every weight zero except the term named.
TrajectoryCostWeights Only(const std::string& term) {
  TrajectoryCostWeights w;
  w.yaw_jerk = term == "energy" ? 0.33 : 0.0;
  w.arc_length_jerk = term == "energy" ? 1.0 : 0.0;
  w.time = term == "time" ? 50.0 : 0.0;
  w.traversability = term == "traversability" ? 50.0 : 0.0;
  w.limits =
      term == "limits" || term == "terrain_speed" || term == "tilt" || term == "step" ? 1.0e3 : 0.0;
  w.clearance = term == "clearance" || term == "body_clearance" ? 1.0e3 : 0.0;
  w.moving_obstacles = term == "moving_obstacles" ? 1.0e3 : 0.0;
  return w;
}

// A 5-piece trajectory roughly along +x from (0, 0) with tight limits so that they are active.
TrajectoryCostSetup CostSetup(const std::string& term) {
  TrajectoryCostSetup s;
  s.weights = Only(term);
  s.limits.max_speed_m_s = 0.8;
  s.limits.max_yaw_rate_rad_s = 0.3;
  s.limits.max_acceleration_m_s2 = 0.4;
  s.limits.max_yaw_acceleration_rad_s2 = 0.3;
  s.limits.max_centripetal_acceleration_m_s2 = 0.1;
  s.clearance_m = 0.8;
  // the terrain's speed limit alone (between 0.5 and 1.3 m/s on the test map)
  if (term == "terrain_speed" || term == "tilt" || term == "step") {
    s.limits = DynamicLimits{10.0, 10.0, 10.0, 10.0, 100.0};
  }
  // the footprint's boundary keeps the clearance: the yaw enters the term too
  if (term == "body_clearance") {
    s.body_points_B = common::Footprint{}.BoundaryPoints_B(0.2);
    s.body_reach_m = common::Footprint{}.CircumscribedRadius();  // far nodes skip the points
    s.clearance_m = 0.3;
  }
  s.start_time_s = 3.0;
  s.start_W = Eigen::Vector2d(0.0, 0.1);
  s.head << 0.1, 0.0, 0.2, 0.5, 0.0, 0.1;
  s.goal_W = Eigen::Vector2d(4.0, 0.3);
  // crossing the path around t = 6 s, and one ahead
  s.obstacles.push_back({Eigen::Vector2d(2.0, -1.5), Eigen::Vector2d(0.0, 0.5), 0.3, 3.0});
  s.obstacles.push_back({Eigen::Vector2d(3.5, 0.6), Eigen::Vector2d(-0.3, 0.0), 0.25, 4.0});
  return s;
}

Eigen::VectorXd InitialZ(std::uint64_t seed) {
  common::Random random(seed);
  const int n = 5;
  Eigen::VectorXd z(3 * n);
  for (int i = 0; i < n - 1; ++i) {
    z(i) = random.Uniform(-0.4, 0.4);                          // yaw
    z(n - 1 + i) = 0.8 * (i + 1) + random.Uniform(-0.1, 0.1);  // arc length
  }
  z(2 * n - 2) = random.Uniform(-0.3, 0.3);
  z(2 * n - 1) = 4.1;
  for (int i = 0; i < n; ++i) {
    z(2 * n + i) = TrajectoryCost::VirtualFromDuration(random.Uniform(0.6, 1.6));
  }
  return z;
}

// The fields' settings: for the terrain's speed limit, a rough speed below the test's speeds.
CostMapConfig FieldConfig(const std::string& term) {
  CostMapConfig config;
  if (term == "terrain_speed") {
    config.speed.smooth_m = 0.0;
    config.speed.rough_m = 0.04;
    config.speed.rough_m_s = 0.4;
  } else {
    config.speed.rough_m_s = 100.0;  // no speed limit
  }
  // the test map's slopes reach 29 deg: pitch and roll limits of 10 and 12 deg are active (and
  // out of the way of the other terms)
  config.slope.max_pitch_deg = term == "tilt" ? 10.0 : 80.0;
  config.slope.max_roll_deg = term == "tilt" ? 12.0 : 80.0;
  // the test map's roughness (up to 0.035 m) reads as steps of up to 0.07 m: with steps from
  // 0.02 m, 0.3 m of reach and 5 deg from square the term is active; by default it reads none
  if (term == "step") {
    config.steps.low_height_m = 0.02;
    config.steps.full_height_m = 0.08;
    config.steps.max_angle_deg = 5.0;
    config.steps.reach_m = 0.3;
  }
  return config;
}

class TrajectoryCostGradientTest : public testing::TestWithParam<std::string> {};

TEST_P(TrajectoryCostGradientTest, MatchesCentralDifferences) {
  const common::GridLayers map = TestMap();
  const CostField field(map, FieldConfig(GetParam()));
  TrajectoryCost dut(field, CostSetup(GetParam()), 5);
  if (GetParam() == "terminal")
    dut.SetTerminalMultiplier(Eigen::Vector2d(3.0, -2.0), 50.0);
  else
    dut.SetTerminalMultiplier(Eigen::Vector2d::Zero(), 1e-300);
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const Eigen::VectorXd z = InitialZ(seed);
    Eigen::VectorXd gradient;
    CostTerms terms;
    const double value = dut.Evaluate(z, &gradient, &terms);
    // the term under test is active
    const double term_value = GetParam() == "energy"             ? terms.energy
                              : GetParam() == "time"             ? terms.time
                              : GetParam() == "traversability"   ? terms.traversability
                              : GetParam() == "limits"           ? terms.limits
                              : GetParam() == "terrain_speed"    ? terms.limits
                              : GetParam() == "tilt"             ? terms.limits
                              : GetParam() == "step"             ? terms.limits
                              : GetParam() == "clearance"        ? terms.clearance
                              : GetParam() == "body_clearance"   ? terms.clearance
                              : GetParam() == "moving_obstacles" ? terms.moving_obstacles
                                                                 : terms.terminal;
    ASSERT_GT(term_value, 0.0) << GetParam() << " inactive for seed " << seed;
    if (GetParam() != "terminal") {
      EXPECT_NEAR(value, term_value, 1e-9 * value);
    }
    const double h = 1e-6;
    for (int i = 0; i < z.size(); ++i) {
      Eigen::VectorXd plus = z, minus = z;
      plus(i) += h;
      minus(i) -= h;
      const double fd = (dut.Evaluate(plus, nullptr) - dut.Evaluate(minus, nullptr)) / (2 * h);
      EXPECT_NEAR(gradient(i), fd, 2e-5 * (1.0 + std::abs(fd)) + 1e-6 * gradient.norm())
          << GetParam() << " variable " << i << " seed " << seed;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryTerm, TrajectoryCostGradientTest,
                         testing::Values("energy", "time", "traversability", "limits",
                                         "terrain_speed", "tilt", "step", "clearance",
                                         "body_clearance", "moving_obstacles", "terminal"),
                         [](const testing::TestParamInfo<std::string>& param_info) {
                           return param_info.param;
                         });

// A plane rising along x at `angle_deg`, free everywhere.
common::GridLayers SlopeMap(double angle_deg) {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(20, 20), 0.1),
      {"traversability", "elevation"});
  map.Layer("traversability").setConstant(0.0f);
  const common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      map.Layer("elevation")(ix, iy) =
          static_cast<float>(std::tan(angle_deg * M_PI / 180.0) * g.CellCenter(ix, iy).x());
    }
  }
  return map;
}

// The limits term of a 3 m straight drive in 3 s from the origin along the heading `yaw` on
// `field`, every other term off.
double TiltCost(const CostField& field, double yaw) {
  TrajectoryCostSetup s;
  s.weights = Only("tilt");
  s.limits = DynamicLimits{10.0, 10.0, 10.0, 10.0, 100.0};
  s.head << yaw, 0.0, 0.0, 0.0, 0.0, 0.0;
  s.goal_W = 3.0 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  TrajectoryCost cost(field, s, 1);
  Eigen::VectorXd z(3);
  z << yaw, 3.0, TrajectoryCost::VirtualFromDuration(3.0);
  CostTerms terms;
  cost.Evaluate(z, nullptr, &terms);
  return terms.limits;
}

TEST(TrajectoryCostTest, TiltIsPenalisedAlongTheHeadingThatExceedsItsLimit) {
  // a 30 deg slope rising along x: climbing it pitches 30 deg (over a 25 deg pitch limit), crossing
  // it rolls 30 deg (within a 35 deg roll limit)
  const common::GridLayers map = SlopeMap(30.0);
  CostMapConfig config;
  config.slope.max_pitch_deg = 25.0;
  config.slope.max_roll_deg = 35.0;
  const CostField field(map, config);
  EXPECT_NEAR(field.Elevation({1.03, 0.2}).gradient_W.x(), std::tan(30.0 * M_PI / 180.0), 1e-6);
  EXPECT_NEAR(field.Elevation({1.03, 0.2}).cross_derivative, 0.0, 1e-6);
  // (tan^2 30 - tan^2 25 - mu / 2) over 3 s, times the weight
  const double pitch_excess = std::pow(std::tan(30.0 * M_PI / 180.0), 2) -
                              std::pow(std::tan(25.0 * M_PI / 180.0), 2) - 0.5e-2;
  EXPECT_NEAR(TiltCost(field, 0.0), 1.0e3 * 3.0 * pitch_excess, 0.1);  // the elevation is float
  EXPECT_NEAR(TiltCost(field, M_PI), 1.0e3 * 3.0 * pitch_excess, 0.1);
  EXPECT_EQ(TiltCost(field, 0.5 * M_PI), 0.0);
}

TEST(TrajectoryCostTest, TheScoutMinisTiltLimitsChargeA45DegSlopeClimbedStraightNotDiagonally) {
  // 40 deg of pitch and of roll, measured (docs/navigation.md): straight up, down or across a
  // 45 deg slope is charged, diagonally (35.3 deg of pitch and of roll) it is not, nor straight up
  // or across 35 deg
  CostMapConfig config;
  config.slope.max_pitch_deg = 40.0;
  config.slope.max_roll_deg = 40.0;
  const common::GridLayers steep = SlopeMap(45.0);
  const CostField steep_field(steep, config);
  EXPECT_GT(TiltCost(steep_field, 0.0), 0.0);
  EXPECT_GT(TiltCost(steep_field, M_PI), 0.0);
  EXPECT_EQ(TiltCost(steep_field, 0.25 * M_PI), 0.0);
  EXPECT_GT(TiltCost(steep_field, 0.5 * M_PI), 0.0);
  const common::GridLayers moderate = SlopeMap(35.0);
  const CostField moderate_field(moderate, config);
  EXPECT_EQ(TiltCost(moderate_field, 0.0), 0.0);
  EXPECT_EQ(TiltCost(moderate_field, 0.5 * M_PI), 0.0);
  // the defaults leave the term out
  EXPECT_FALSE(CostMapConfig{}.slope.Active());
  EXPECT_EQ(TiltCost(CostField(steep, CostMapConfig{}), 0.0), 0.0);
}

TEST(TrajectoryCostTest, IntegratesAStraightMotionToItsArcLength) {
  // from rest to rest along yaw 0.3: the integrated end position is s_T (cos 0.3, sin 0.3) up to
  // Simpson's error (exact for cubics; v is a quartic here, h = 1/8 s)
  const common::GridLayers map = TestMap();
  const CostField field(map, CostMapConfig{});
  TrajectoryCostSetup setup;
  setup.head << 0.3, 0.0, 0.0, 0.0, 0.0, 0.0;
  TrajectoryCost dut(field, setup, 3);
  Eigen::VectorXd z(9);
  z << 0.3, 0.3, 1.0, 2.0, 0.3, 3.0, 0.0, 0.0, 0.0;
  dut.Evaluate(z, nullptr);
  EXPECT_NEAR(dut.end_position_W().x(), 3.0 * std::cos(0.3), 2e-5);
  EXPECT_NEAR(dut.end_position_W().y(), 3.0 * std::sin(0.3), 2e-5);
  EXPECT_NEAR(std::atan2(dut.end_position_W().y(), dut.end_position_W().x()), 0.3, 1e-12);
}

TEST(TrajectoryCostTest, SmoothedL1AndTheDurationMapAreC1AndInverse) {
  double slope = 0.0;
  EXPECT_EQ(SmoothedL1(-1.0, 0.01, &slope), 0.0);
  EXPECT_EQ(slope, 0.0);
  EXPECT_NEAR(SmoothedL1(0.01, 0.01, &slope), 0.005, 1e-15);
  EXPECT_NEAR(slope, 1.0, 1e-12);
  EXPECT_NEAR(SmoothedL1(2.0, 0.01, &slope), 1.995, 1e-15);
  for (double tau : {-3.0, -0.5, 0.0, 0.7, 4.0}) {
    const double duration = TrajectoryCost::DurationFromVirtual(tau);
    EXPECT_GT(duration, 0.0);
    EXPECT_NEAR(TrajectoryCost::VirtualFromDuration(duration), tau, 1e-12);
    const double fd = (TrajectoryCost::DurationFromVirtual(tau + 1e-6) -
                       TrajectoryCost::DurationFromVirtual(tau - 1e-6)) /
                      2e-6;
    EXPECT_NEAR(TrajectoryCost::DurationGradient(tau), fd, 1e-7);
  }
}

}  // namespace
}  // namespace trav::planner
