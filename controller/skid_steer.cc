#include "controller/skid_steer.h"

#include <algorithm>
#include <cmath>

namespace trav::controller {

using common::Wheel;

common::WheelSpeeds ToWheelSpeeds(const common::Twist2& command, const SkidSteerConfig& config) {
  double v = std::clamp(command.v, -config.max_speed_m_s, config.max_speed_m_s);
  double omega = std::clamp(command.omega, -config.max_yaw_rate_rad_s, config.max_yaw_rate_rad_s);
  const double half_track = 0.5 * config.effective_track_factor * config.track_m;
  double left = (v - omega * half_track) / config.wheel_radius_m;
  double right = (v + omega * half_track) / config.wheel_radius_m;
  // keep the curvature when a wheel saturates
  const double largest = std::max(std::abs(left), std::abs(right));
  if (largest > config.max_wheel_speed_rad_s) {
    const double scale = config.max_wheel_speed_rad_s / largest;
    left *= scale;
    right *= scale;
  }
  common::WheelSpeeds speeds{};
  speeds[static_cast<int>(Wheel::kFrontLeft)] = left;
  speeds[static_cast<int>(Wheel::kRearLeft)] = left;
  speeds[static_cast<int>(Wheel::kFrontRight)] = right;
  speeds[static_cast<int>(Wheel::kRearRight)] = right;
  return speeds;
}

common::Twist2 FromWheelSpeeds(const common::WheelSpeeds& wheel_speeds_rad_s,
                               const SkidSteerConfig& config) {
  const double left = 0.5 * (wheel_speeds_rad_s[static_cast<int>(Wheel::kFrontLeft)] +
                             wheel_speeds_rad_s[static_cast<int>(Wheel::kRearLeft)]);
  const double right = 0.5 * (wheel_speeds_rad_s[static_cast<int>(Wheel::kFrontRight)] +
                              wheel_speeds_rad_s[static_cast<int>(Wheel::kRearRight)]);
  common::Twist2 twist;
  twist.v = 0.5 * config.wheel_radius_m * (left + right);
  twist.omega =
      config.wheel_radius_m * (right - left) / (config.effective_track_factor * config.track_m);
  return twist;
}

}  // namespace trav::controller
