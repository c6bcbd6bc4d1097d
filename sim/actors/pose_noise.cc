#include "sim/actors/pose_noise.h"

#include <algorithm>
#include <cmath>

#include "common/input_error.h"

namespace trav::sim {

void ValidatePoseNoiseConfig(const PoseNoiseConfig& c) {
  using common::RequireValue;
  RequireValue(c.position_noise_m >= 0.0, "position_noise", c.position_noise_m, "must be >= 0");
  RequireValue(c.yaw_noise_rad >= 0.0, "yaw_noise", c.yaw_noise_rad, "must be >= 0");
  RequireValue(c.drift_m_per_sqrt_s >= 0.0, "drift", c.drift_m_per_sqrt_s, "must be >= 0");
}

void ValidateOdometryDriftConfig(const OdometryDriftConfig& o) {
  using common::RequireValue;
  RequireValue(o.translation_m_per_sqrt_m >= 0.0, "translation_drift", o.translation_m_per_sqrt_m,
               "must be >= 0");
  RequireValue(o.z_m_per_sqrt_m >= 0.0, "z_drift", o.z_m_per_sqrt_m, "must be >= 0");
  RequireValue(o.yaw_rad_per_sqrt_m >= 0.0, "yaw_drift", o.yaw_rad_per_sqrt_m, "must be >= 0");
}

PoseNoise::PoseNoise(const PoseNoiseConfig& config) : config_(config), random_(config.seed) {}

void PoseNoise::DriftAlong(const Eigen::Vector3d& p_W) {
  if (!last_p_W_) {
    last_p_W_ = p_W;
    return;
  }
  const Eigen::Vector3d step_W = p_W - *last_p_W_;
  last_p_W_ = p_W;
  const double root = std::sqrt(step_W.norm());
  const OdometryDriftConfig& o = config_.odometry;
  // the step as the drifted odometry integrates it: turned by the yaw error so far
  const Eigen::Vector3d turned_W =
      Eigen::AngleAxisd(odometry_yaw_error_rad_, Eigen::Vector3d::UnitZ()) * step_W;
  const double ex = random_.Normal();
  const double ey = random_.Normal();
  const double ez = random_.Normal();
  odometry_position_error_W_ +=
      turned_W - step_W +
      root * Eigen::Vector3d(o.translation_m_per_sqrt_m * ex, o.translation_m_per_sqrt_m * ey,
                             o.z_m_per_sqrt_m * ez);
  odometry_yaw_error_rad_ += root * o.yaw_rad_per_sqrt_m * random_.Normal();
}

common::RobotState PoseNoise::Estimate(const common::RobotState& truth) {
  const PoseNoiseConfig& c = config_;
  if (!c.active()) return truth;
  const double dt = std::max(0.0, truth.time_s - last_time_s_);
  last_time_s_ = truth.time_s;
  common::RobotState estimate = truth;
  if (c.method == LocalizationMethod::kDriftModel) {
    DriftAlong(truth.X_WB.translation());
    estimate.X_WB.translation() += odometry_position_error_W_;
    estimate.X_WB.linear() =
        Eigen::AngleAxisd(odometry_yaw_error_rad_, Eigen::Vector3d::UnitZ()) * truth.X_WB.linear();
  }
  if (c.position_noise_m == 0.0 && c.yaw_noise_rad == 0.0 && c.drift_m_per_sqrt_s == 0.0) {
    return estimate;
  }
  const double step = c.drift_m_per_sqrt_s * std::sqrt(dt);
  drift_W_ += step * Eigen::Vector2d(random_.Normal(), random_.Normal());
  estimate.X_WB.translation().head<2>() +=
      drift_W_ + c.position_noise_m * Eigen::Vector2d(random_.Normal(), random_.Normal());
  estimate.X_WB.linear() =
      Eigen::AngleAxisd(c.yaw_noise_rad * random_.Normal(), Eigen::Vector3d::UnitZ()) *
      estimate.X_WB.linear();
  return estimate;
}

}  // namespace trav::sim
