#include "sim/actors/pose_noise.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "common/input_error.h"

namespace trav::sim {

void ValidatePoseNoiseConfig(const PoseNoiseConfig& c) {
  using common::RequireValue;
  RequireValue(c.position_noise_m >= 0.0, "position_noise", c.position_noise_m, "must be >= 0");
  RequireValue(c.yaw_noise_rad >= 0.0, "yaw_noise", c.yaw_noise_rad, "must be >= 0");
  RequireValue(c.drift_m_per_sqrt_s >= 0.0, "drift", c.drift_m_per_sqrt_s, "must be >= 0");
}

PoseNoise::PoseNoise(const PoseNoiseConfig& config) : config_(config), random_(config.seed) {}

common::RobotState PoseNoise::Estimate(const common::RobotState& truth) {
  const PoseNoiseConfig& c = config_;
  if (c.position_noise_m == 0.0 && c.yaw_noise_rad == 0.0 && c.drift_m_per_sqrt_s == 0.0) {
    return truth;
  }
  const double dt = std::max(0.0, truth.time_s - last_time_s_);
  last_time_s_ = truth.time_s;
  const double step = c.drift_m_per_sqrt_s * std::sqrt(dt);
  drift_W_ += step * Eigen::Vector2d(random_.Normal(), random_.Normal());
  common::RobotState estimate = truth;
  estimate.X_WB.translation().head<2>() +=
      drift_W_ + c.position_noise_m * Eigen::Vector2d(random_.Normal(), random_.Normal());
  estimate.X_WB.linear() =
      Eigen::AngleAxisd(c.yaw_noise_rad * random_.Normal(), Eigen::Vector3d::UnitZ()) *
      truth.X_WB.linear();
  return estimate;
}

}  // namespace trav::sim
