#include "controller/mpc.h"

#include <cmath>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"

namespace trav::controller {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;
using ::testing::ThrowsMessage;

std::vector<Eigen::Vector2d> Line(double length) {
  std::vector<Eigen::Vector2d> path;
  for (double s = 0.0; s <= length + 1e-9; s += 0.01) path.emplace_back(s, 0.0);
  return path;
}

std::vector<Eigen::Vector2d> Circle(double radius) {
  std::vector<Eigen::Vector2d> path;
  for (double a = 0.0; a <= 2.0 * M_PI + 1e-9; a += 0.01 / radius) {
    path.emplace_back(radius * std::sin(a), radius * (1.0 - std::cos(a)));
  }
  return path;
}

// Lemniscate of Gerono through the origin, heading +x at the start.
std::vector<Eigen::Vector2d> FigureEight(double half_width) {
  std::vector<Eigen::Vector2d> path;
  for (double a = 0.0; a <= 2.0 * M_PI + 1e-9; a += 0.002) {
    path.emplace_back(half_width * std::sin(a), half_width * std::sin(a) * std::cos(a));
  }
  return path;
}

struct TrackingRun {
  std::vector<double> lateral_errors;  // after the first 2 s
  std::vector<common::Twist2> commands;
  std::vector<MpcStatus> statuses;
};

// A kinematic unicycle (exact, 1 ms steps) under the MPC at 50 Hz, starting at `start`.
TrackingRun Track(const common::Trajectory& reference, const MpcConfig& config,
                  const MpcState& start) {
  MpcController dut(config);
  MpcState state = start;
  TrackingRun run;
  common::Twist2 command;
  const int substeps = static_cast<int>(std::lround(config.control_period_s / 0.001));
  for (double t = 0.0; t < reference.end_time() + 1.0; t += config.control_period_s) {
    const MpcResult result = dut.Solve(state, reference, t);
    run.statuses.push_back(result.status);
    command = result.command;
    run.commands.push_back(command);
    for (int i = 0; i < substeps; ++i) {
      state.position_W +=
          0.001 * command.v * Eigen::Vector2d(std::cos(state.yaw), std::sin(state.yaw));
      state.yaw += 0.001 * command.omega;
    }
    state.v = command.v;
    state.omega = command.omega;
    const common::TrajectoryPoint r = reference.Sample(t + config.control_period_s);
    const Eigen::Vector2d e = state.position_W - r.position_W;
    if (t > 2.0) run.lateral_errors.push_back(-std::sin(r.yaw) * e.x() + std::cos(r.yaw) * e.y());
  }
  return run;
}

double Rms(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v * v;
  return std::sqrt(sum / values.size());
}

double MaxAbs(const std::vector<double>& values) {
  double m = 0.0;
  for (double v : values) m = std::max(m, std::abs(v));
  return m;
}

void ExpectWithinLimits(const TrackingRun& run, const MpcConfig& config) {
  common::Twist2 previous;
  for (const common::Twist2& u : run.commands) {
    ASSERT_LE(u.v, config.max_speed_m_s + 1e-12);
    ASSERT_GE(u.v, config.min_speed_m_s - 1e-12);
    ASSERT_LE(std::abs(u.omega), config.max_yaw_rate_rad_s + 1e-12);
    ASSERT_LE(std::abs(u.v - previous.v),
              config.max_acceleration_m_s2 * config.control_period_s + 1e-12);
    ASSERT_LE(std::abs(u.omega - previous.omega),
              config.max_yaw_acceleration_rad_s2 * config.control_period_s + 1e-12);
    previous = u;
  }
}

TEST(MpcTest, TracksALineACircleAndAFigureEight) {
  const MpcConfig config;
  for (const auto& [name, path] : {std::pair{"line", Line(10.0)}, std::pair{"circle", Circle(2.0)},
                                   std::pair{"figure-eight", FigureEight(3.0)}}) {
    const common::Trajectory reference = common::TrajectoryAlongPath(path, 1.0, 1.0);
    const TrackingRun run = Track(reference, config, MpcState{});
    EXPECT_LT(Rms(run.lateral_errors), 0.01) << name;
    EXPECT_LT(MaxAbs(run.lateral_errors), 0.03) << name;
    ExpectWithinLimits(run, config);
    for (MpcStatus status : run.statuses) ASSERT_NE(status, MpcStatus::kFailed) << name;
  }
}

TEST(MpcTest, RecoversSmoothlyFromAMetreOff) {
  MpcConfig config;
  const common::Trajectory reference = common::TrajectoryAlongPath(Line(20.0), 1.0, 1.0);
  MpcState start;
  start.position_W = Eigen::Vector2d(0.0, 1.0);
  const TrackingRun run = Track(reference, config, start);
  ExpectWithinLimits(run, config);
  // converged after a few seconds, without overshooting to the other side by more than 10 cm
  EXPECT_LT(std::abs(run.lateral_errors.back()), 0.01);
  double most_negative = 0.0;
  for (double e : run.lateral_errors) most_negative = std::min(most_negative, e);
  EXPECT_GT(most_negative, -0.10);
}

TEST(MpcTest, SameInputsGiveTheSameCommands) {
  const common::Trajectory reference = common::TrajectoryAlongPath(FigureEight(3.0), 1.0, 1.0);
  // no wall-time budget: the solve is a function of its inputs alone
  const MpcConfig config;
  const TrackingRun a = Track(reference, config, MpcState{});
  const TrackingRun b = Track(reference, config, MpcState{});
  ASSERT_EQ(a.commands.size(), b.commands.size());
  for (std::size_t i = 0; i < a.commands.size(); ++i) {
    ASSERT_EQ(a.commands[i].v, b.commands[i].v);
    ASSERT_EQ(a.commands[i].omega, b.commands[i].omega);
  }
}

TEST(MpcTest, ActuatorLagModelStillTracks) {
  MpcConfig config;
  config.actuator_time_constant_s = 0.05;
  const common::Trajectory reference = common::TrajectoryAlongPath(Circle(2.0), 1.0, 1.0);
  const TrackingRun run = Track(reference, config, MpcState{});
  EXPECT_LT(Rms(run.lateral_errors), 0.03);
}

TEST(MpcTest, BadConfigurationsAreInputErrors) {
  MpcConfig config;
  config.horizon = -3;
  EXPECT_THAT([&] { MpcController dut(config); },
              ThrowsMessage<common::InputError>(StartsWith("horizon: value -3")));
  config = MpcConfig();
  config.state_weights = Eigen::Vector3d(1.0, -1.0, 1.0);
  EXPECT_THAT([&] { MpcController dut(config); },
              ThrowsMessage<common::InputError>(StartsWith("state_weights: value -1")));
  config = MpcConfig();
  config.max_speed_m_s = 0.0;
  EXPECT_THAT([&] { MpcController dut(config); },
              ThrowsMessage<common::InputError>(HasSubstr("max_speed")));
}

}  // namespace
}  // namespace trav::controller
