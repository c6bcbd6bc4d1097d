#include "scenarios/run/calibration.h"

#include <algorithm>
#include <string>

#include <gtest/gtest.h>

namespace trav::scenarios {
namespace {

// The documented default of effective_track_factor must be what the model measures: if the MJCF
// changes, this fails until the default (and docs/skid-steer-calibration.md) are updated.
TEST(CalibrationTest, DefaultEffectiveTrackFactorMatchesTheModel) {
  const controller::SkidSteerConfig config;
  const CalibrationResult dut =
      CalibrateSkidSteer(std::string(TRAV_MODELS_DIR) + "/scout_mini.xml", config);
  ASSERT_EQ(dut.samples.size(), 6u);
  EXPECT_NEAR(dut.effective_track_factor, config.effective_track_factor,
              0.03 * config.effective_track_factor);
  for (const CalibrationSample& sample : dut.samples) {
    EXPECT_NEAR(sample.measured_omega_rad_s, sample.commanded_omega_rad_s,
                0.05 * std::max(1.0, sample.commanded_omega_rad_s));
    EXPECT_NEAR(sample.measured_v_m_s, sample.commanded_v_m_s,
                0.03 * std::max(1.0, sample.commanded_v_m_s));
  }
}

TEST(CalibrationTest, AnUncalibratedMappingTurnsFarTooSlowly) {
  controller::SkidSteerConfig config;
  config.effective_track_factor = 1.0;
  const CalibrationResult dut =
      CalibrateSkidSteer(std::string(TRAV_MODELS_DIR) + "/scout_mini.xml", config);
  // about 40 % of the commanded yaw rate with the geometric track
  EXPECT_LT(dut.samples[1].measured_omega_rad_s, 0.5);
  EXPECT_GT(dut.effective_track_factor, 2.2);
  EXPECT_LT(dut.effective_track_factor, 2.8);
}

}  // namespace
}  // namespace trav::scenarios
