#pragma once

#include "common/archive.h"
#include "common/pose.h"

namespace trav::controller {

/// Geometry and limits of a four-wheel skid-steer base (defaults: AgileX Scout Mini in trav's
/// MuJoCo model, models/scout_mini.xml).
struct SkidSteerConfig {
  double wheel_radius_m{0.0875};  ///< [m], > 0
  double track_m{0.49};           ///< distance between left and right wheel centres [m], > 0
  /// Effective track B_eff / B: a skid-steer base turns slower than a differential drive with the
  /// same wheel speeds because its wheels scrub sideways. Measured in simulation by spinning in
  /// place (docs/skid-steer-calibration.md; `trav calibrate` reproduces it). >= 1.
  double effective_track_factor{2.48};
  double max_speed_m_s{3.0};           ///< top forward speed [m/s]
  double max_yaw_rate_rad_s{2.5};      ///< top yaw rate [rad/s]
  double max_wheel_speed_rad_s{35.0};  ///< motor limit [rad/s]

  /// The keys of scenario section `robot.skid_steer` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("wheel_radius", &wheel_radius_m, {0.01, 2.0});
    a->Field("track", &track_m, {0.05, 10.0});
    a->Field("effective_track_factor", &effective_track_factor, {1.0, 20.0});
    a->Field("max_speed", &max_speed_m_s, {0.01, 30.0});
    a->Field("max_yaw_rate", &max_yaw_rate_rad_s, {0.01, 30.0});
    a->Field("max_wheel_speed", &max_wheel_speed_rad_s, {0.1, 1000.0});
  }
};

/// Maps a body twist (v, omega) to the four wheel speeds [rad/s] with the effective track:
/// left = (v - omega B_eff / 2) / r, right = (v + omega B_eff / 2) / r. The command is first
/// clamped to the speed and yaw-rate limits; if a wheel would still exceed its limit, v and omega
/// are scaled down together so the path curvature is kept.
common::WheelSpeeds ToWheelSpeeds(const common::Twist2& command, const SkidSteerConfig& config);

/// Inverse of ToWheelSpeeds (without limits): the twist the wheel speeds produce, averaging each
/// side (wheel odometry).
common::Twist2 FromWheelSpeeds(const common::WheelSpeeds& wheel_speeds_rad_s,
                               const SkidSteerConfig& config);

}  // namespace trav::controller
