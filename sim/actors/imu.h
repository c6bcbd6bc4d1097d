#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "common/archive.h"
#include "common/random.h"
#include "sim/simulation.h"

namespace trav::sim {

/// The IMU the stack reads (scenario section `imu`): the model's accelerometer and gyroscope at
/// its `imu` site, sampled at `rate`, with white noise and a bias random walk per axis (the
/// continuous-time model of Kalibr and the ROS IMU tools). Defaults: the MID-360's built-in IMU,
/// a TDK ICM-40609 (datasheet DS-000330: accelerometer noise 100 ug/sqrt(Hz), gyroscope noise
/// 4.5 mdps/sqrt(Hz)); the datasheet gives no bias random walk, so those are the figures of the
/// EuRoC dataset's Kalibr calibration of its MEMS IMU (ADIS16448: 3.0e-3 m/s^3/sqrt(Hz),
/// 1.9393e-5 rad/s^2/sqrt(Hz)), a conservative bound for a sensor of this class.
struct ImuConfig {
  bool enabled{true};
  double rate_hz{200.0};                    ///< samples per second
  double accel_noise_density{9.80665e-4};   ///< [m/s^2/sqrt(Hz)]
  double gyro_noise_density{7.853982e-5};   ///< [rad/s/sqrt(Hz)]
  double accel_bias_random_walk{3.0e-3};    ///< [m/s^3/sqrt(Hz)]
  double gyro_bias_random_walk{1.9393e-5};  ///< [rad/s^2/sqrt(Hz)]
  std::uint64_t seed{1};                    ///< noise and bias draws

  /// The keys of scenario section `imu` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("enabled", &enabled);
    a->Field("rate", &rate_hz, {1, 2000});
    a->Field("accel_noise_density", &accel_noise_density, {0, 1});
    a->Field("gyro_noise_density", &gyro_noise_density, {0, 1});
    a->Field("accel_bias_random_walk", &accel_bias_random_walk, {0, 1});
    a->Field("gyro_bias_random_walk", &gyro_bias_random_walk, {0, 1});
    a->Field("seed", &seed);
  }
};

/// Checks a config. @throws common::InputError naming the key (relative: "rate") and value.
void ValidateImuConfig(const ImuConfig& config);

/// One IMU sample: its time, the measurement and the true values it was made from.
struct ImuSample {
  double t_s{0.0};
  ImuMeasurement measured;
  ImuMeasurement truth;
};

/// The IMU: turns the true readings of the physics steps into samples at exactly t = k / rate,
/// each interpolated linearly between the two readings around it, with white noise of standard
/// deviation density * sqrt(rate) and biases that walk by random_walk / sqrt(rate) per sample,
/// starting at zero. Seeded and repeatable.
class Imu {
 public:
  /// @throws common::InputError naming the key for a config out of range (ValidateImuConfig).
  explicit Imu(const ImuConfig& config);

  /// Takes the true reading of the state at time t_s (after the previous reading's time) and
  /// replaces samples() by the samples due in (previous reading's time, t_s]; the first reading
  /// gives the samples due up to t_s.
  void AddReading(double t_s, const ImuMeasurement& truth);

  /// The samples of the last reading (none, one or several).
  const std::vector<ImuSample>& samples() const { return samples_; }

  /// The current biases.
  const ImuMeasurement& bias() const { return bias_; }

 private:
  ImuSample Sample(double t_s, const ImuMeasurement& truth);

  ImuConfig config_;
  common::Random random_;
  ImuMeasurement bias_;
  std::int64_t next_sample_{0};
  std::optional<std::pair<double, ImuMeasurement>> previous_reading_;
  std::vector<ImuSample> samples_;
};

/// `R` turned on by the rotation the gyroscopes of `samples` measured, each sample's rate held for
/// 1 / rate_hz (R exp(w_1 dt) exp(w_2 dt) ...): the IMU frame's rotation over the samples when R is
/// the identity.
Eigen::Matrix3d IntegrateGyro(const Eigen::Matrix3d& R, const std::vector<ImuSample>& samples,
                              double rate_hz);

}  // namespace trav::sim
