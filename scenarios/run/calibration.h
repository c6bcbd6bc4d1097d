#pragma once

#include <string>
#include <vector>

#include "controller/skid_steer.h"
#include "scenarios/run/output_folder.h"

namespace trav::scenarios {

/// One measurement of the skid-steer calibration on flat ground.
struct CalibrationSample {
  double commanded_v_m_s{0.0};
  double commanded_omega_rad_s{0.0};
  double measured_v_m_s{0.0};        ///< mean forward speed over the measuring window
  double measured_omega_rad_s{0.0};  ///< mean yaw rate over the measuring window
};

/// Result of CalibrateSkidSteer.
struct CalibrationResult {
  std::vector<CalibrationSample> samples;
  /// The factor that makes the measured yaw rates match the commanded ones on average:
  /// current factor x mean(commanded / measured yaw rate) over the spin samples.
  double effective_track_factor{0.0};
};

/// Measures the robot on flat ground in MuJoCo: spins in place at 0.5, 1 and 2 rad/s and drives
/// straight at 0.5, 1 and 2 m/s with `config` (1 s to settle, 1 s to spin up, 2 s measured each).
/// Deterministic; takes about a second.
CalibrationResult CalibrateSkidSteer(const std::string& robot_model_path,
                                     const controller::SkidSteerConfig& config);

/// Writes `result` into `folder`: calibration.csv (one row per sample: commanded and measured v
/// [m/s] and omega [rad/s]) and calibration.json (the samples, the factor measured with and the
/// factor that matches).
void WriteCalibration(const CalibrationResult& result, const controller::SkidSteerConfig& used,
                      const OutputFolder& folder);

}  // namespace trav::scenarios
