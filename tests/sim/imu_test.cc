#include "sim/actors/imu.h"

#include <cmath>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"

namespace trav::sim {
namespace {

ImuMeasurement Constant(double accel_z, double gyro_z) {
  ImuMeasurement m;
  m.accel_I.z() = accel_z;
  m.gyro_I.z() = gyro_z;
  return m;
}

ImuConfig Noiseless() {
  ImuConfig config;
  config.accel_noise_density = 0.0;
  config.gyro_noise_density = 0.0;
  config.accel_bias_random_walk = 0.0;
  config.gyro_bias_random_walk = 0.0;
  return config;
}

TEST(ImuTest, SamplesAtExactlyTheRateInterpolatedBetweenPhysicsSteps) {
  Imu dut(Noiseless());  // 200 Hz from 2 ms steps: 5 ms is two and a half steps
  std::vector<ImuSample> samples;
  for (int step = 0; step <= 10; ++step) {
    // a yaw rate rising linearly, 1 rad/s per second
    dut.AddReading(0.002 * step, Constant(9.81, 0.002 * step));
    samples.insert(samples.end(), dut.samples().begin(), dut.samples().end());
  }
  ASSERT_EQ(samples.size(), 5u);  // t = 0, 5, 10, 15, 20 ms
  for (std::size_t k = 0; k < samples.size(); ++k) {
    EXPECT_DOUBLE_EQ(samples[k].t_s, 0.005 * static_cast<double>(k));
    // linear in time, so interpolation is exact
    EXPECT_NEAR(samples[k].measured.gyro_I.z(), 0.005 * static_cast<double>(k), 1e-12);
    EXPECT_EQ(samples[k].measured.accel_I, samples[k].truth.accel_I);
  }
}

TEST(ImuTest, WhiteNoiseAndBiasWalkHaveTheConfiguredSize) {
  ImuConfig config;
  config.accel_bias_random_walk = 0.0;
  config.gyro_bias_random_walk = 0.0;
  Imu white(config);
  const int n = 20000;  // 100 s at 200 Hz
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    white.AddReading(k / 200.0, Constant(9.81, 0.0));
    const double e = white.samples().at(0).measured.accel_I.z() - 9.81;
    sum += e;
    sum2 += e * e;
  }
  // density * sqrt(rate): 100 ug/sqrt(Hz) * sqrt(200 Hz) = 0.01387 m/s^2
  EXPECT_NEAR(std::sqrt(sum2 / n - (sum / n) * (sum / n)), 9.80665e-4 * std::sqrt(200.0),
              0.03 * 9.80665e-4 * std::sqrt(200.0));

  // the gyroscope bias after time T has standard deviation random_walk * sqrt(T): over 400
  // independent IMUs walking for 25 s
  ImuConfig walking = Noiseless();
  walking.gyro_bias_random_walk = 1e-3;
  double bias2 = 0.0;
  for (std::uint64_t seed = 1; seed <= 400; ++seed) {
    walking.seed = seed;
    Imu dut(walking);
    for (int k = 0; k < 5000; ++k) dut.AddReading(k / 200.0, Constant(9.81, 0.0));
    bias2 += dut.bias().gyro_I.squaredNorm() / 3.0;
  }
  EXPECT_NEAR(std::sqrt(bias2 / 400.0), 1e-3 * std::sqrt(25.0), 0.06 * 1e-3 * std::sqrt(25.0));
}

TEST(ImuTest, SameSeedSameSamples) {
  Imu a{ImuConfig{}}, b{ImuConfig{}};
  for (int k = 0; k < 100; ++k) {
    a.AddReading(k * 0.002, Constant(9.81, 0.1));
    b.AddReading(k * 0.002, Constant(9.81, 0.1));
    ASSERT_EQ(a.samples().size(), b.samples().size());
    for (std::size_t i = 0; i < a.samples().size(); ++i) {
      EXPECT_EQ(a.samples()[i].measured.accel_I, b.samples()[i].measured.accel_I);
      EXPECT_EQ(a.samples()[i].measured.gyro_I, b.samples()[i].measured.gyro_I);
    }
  }
}

TEST(ImuTest, ARateOutOfRangeIsAnInputErrorNamingTheKey) {
  ImuConfig config;
  config.rate_hz = 0.0;
  EXPECT_THAT([&] { Imu dut(config); },
              ::testing::ThrowsMessage<common::InputError>(::testing::HasSubstr("rate")));
}

}  // namespace
}  // namespace trav::sim
