#include "sim/actors/imu.h"

#include <algorithm>
#include <cmath>

#include "common/input_error.h"

namespace trav::sim {
namespace {

Eigen::Vector3d NormalVector(common::Random* random) {
  const double x = random->Normal();
  const double y = random->Normal();
  return {x, y, random->Normal()};
}

}  // namespace

void ValidateImuConfig(const ImuConfig& c) {
  using common::RequireValue;
  RequireValue(c.rate_hz > 0.0, "rate", c.rate_hz, "must be > 0");
  RequireValue(c.accel_noise_density >= 0.0, "accel_noise_density", c.accel_noise_density,
               "must be >= 0");
  RequireValue(c.gyro_noise_density >= 0.0, "gyro_noise_density", c.gyro_noise_density,
               "must be >= 0");
  RequireValue(c.accel_bias_random_walk >= 0.0, "accel_bias_random_walk", c.accel_bias_random_walk,
               "must be >= 0");
  RequireValue(c.gyro_bias_random_walk >= 0.0, "gyro_bias_random_walk", c.gyro_bias_random_walk,
               "must be >= 0");
}

Imu::Imu(const ImuConfig& config) : config_(config), random_(config.seed) {
  ValidateImuConfig(config_);
}

void Imu::AddReading(double t_s, const ImuMeasurement& truth) {
  samples_.clear();
  // sample times k / rate, compared with a nanosecond of slack for the rounding of t_s
  for (double t_k = static_cast<double>(next_sample_) / config_.rate_hz; t_k <= t_s + 1e-9;
       t_k = static_cast<double>(next_sample_) / config_.rate_hz) {
    ImuMeasurement at_t_k = truth;
    if (previous_reading_ && t_s > previous_reading_->first) {
      const auto& [t_previous, previous] = *previous_reading_;
      const double w = std::clamp((t_k - t_previous) / (t_s - t_previous), 0.0, 1.0);
      at_t_k.accel_I = (1.0 - w) * previous.accel_I + w * truth.accel_I;
      at_t_k.gyro_I = (1.0 - w) * previous.gyro_I + w * truth.gyro_I;
    }
    samples_.push_back(Sample(t_k, at_t_k));
    ++next_sample_;
  }
  previous_reading_.emplace(t_s, truth);
}

ImuSample Imu::Sample(double t_s, const ImuMeasurement& truth) {
  const double sqrt_rate = std::sqrt(config_.rate_hz);
  // the biases walk first, then the white noise of this sample (fixed draw order: x, y, z of the
  // accelerometer bias, the gyroscope bias, the accelerometer noise, the gyroscope noise)
  bias_.accel_I += (config_.accel_bias_random_walk / sqrt_rate) * NormalVector(&random_);
  bias_.gyro_I += (config_.gyro_bias_random_walk / sqrt_rate) * NormalVector(&random_);
  ImuSample sample;
  sample.t_s = t_s;
  sample.truth = truth;
  sample.measured.accel_I = truth.accel_I + bias_.accel_I +
                            (config_.accel_noise_density * sqrt_rate) * NormalVector(&random_);
  sample.measured.gyro_I = truth.gyro_I + bias_.gyro_I +
                           (config_.gyro_noise_density * sqrt_rate) * NormalVector(&random_);
  return sample;
}

Eigen::Matrix3d IntegrateGyro(const Eigen::Matrix3d& R, const std::vector<ImuSample>& samples,
                              double rate_hz) {
  Eigen::Matrix3d turned = R;
  for (const ImuSample& sample : samples) {
    const Eigen::Vector3d& w = sample.measured.gyro_I;
    const double angle = w.norm() / rate_hz;
    if (angle > 0.0) turned = turned * Eigen::AngleAxisd(angle, w.normalized()).toRotationMatrix();
  }
  return turned;
}

}  // namespace trav::sim
