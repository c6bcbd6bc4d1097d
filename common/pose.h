#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Geometry>

namespace trav::common {

/// Planar pose of a body in a frame: position [m] and yaw [rad] about +z, with a time stamp [s].
struct Pose2 {
  Eigen::Vector2d position{Eigen::Vector2d::Zero()};  ///< [m]
  double yaw{0.0};                                    ///< [rad], counter-clockwise from +x
  double time_s{0.0};                                 ///< [s]
};

/// Spatial pose of a body in a frame (an isometry), with a time stamp [s].
struct Pose3 {
  Eigen::Isometry3d transform{Eigen::Isometry3d::Identity()};
  double time_s{0.0};  ///< [s]
};

/// Planar velocity command of a ground robot, in its base frame B.
struct Twist2 {
  double v{0.0};      ///< forward speed along +x_B [m/s]
  double omega{0.0};  ///< yaw rate about +z_B [rad/s]
};

/// Wheel order used everywhere: front-left, rear-left, front-right, rear-right.
enum class Wheel { kFrontLeft = 0, kRearLeft = 1, kFrontRight = 2, kRearRight = 3 };

/// Angular speeds of the four wheels [rad/s], positive = rolling forward, indexed by Wheel.
using WheelSpeeds = std::array<double, 4>;

/// Full ground-truth state of the robot base B in the world W.
struct RobotState {
  Eigen::Isometry3d X_WB{Eigen::Isometry3d::Identity()};  ///< pose of B in W
  Eigen::Vector3d v_WB_B{
      Eigen::Vector3d::Zero()};  ///< linear velocity of B in W, expressed in B [m/s]
  Eigen::Vector3d w_WB_B{
      Eigen::Vector3d::Zero()};  ///< angular velocity of B in W, expressed in B [rad/s]
  WheelSpeeds wheel_speeds{};    ///< measured wheel speeds [rad/s]
  double time_s{0.0};            ///< simulation time [s]
};

/// Roll, pitch and yaw [rad] (intrinsic z-y-x, as REP-103) of a rotation.
struct RollPitchYaw {
  double roll{0.0};
  double pitch{0.0};
  double yaw{0.0};
};

/// Converts a rotation to roll, pitch, yaw (yaw in (-pi, pi], pitch in [-pi/2, pi/2]).
inline RollPitchYaw ToRollPitchYaw(const Eigen::Matrix3d& R) {
  RollPitchYaw rpy;
  rpy.pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  rpy.roll = std::atan2(R(2, 1), R(2, 2));
  rpy.yaw = std::atan2(R(1, 0), R(0, 0));
  return rpy;
}

/// Tilt of a rotation: the angle [rad] between its z axis and the world's +z.
inline double TiltAngle(const Eigen::Matrix3d& R) {
  return std::acos(std::clamp(R(2, 2), -1.0, 1.0));
}

/// Wraps an angle to (-pi, pi].
inline double WrapAngle(double angle) {
  angle = std::fmod(angle + M_PI, 2.0 * M_PI);
  if (angle <= 0.0) angle += 2.0 * M_PI;
  return angle - M_PI;
}

}  // namespace trav::common
