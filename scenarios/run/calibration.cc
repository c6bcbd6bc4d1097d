#include "scenarios/run/calibration.h"

#include <cmath>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sim/simulation.h"

namespace trav::scenarios {
namespace {

constexpr double kSettle_s = 1.0;
constexpr double kSpinUp_s = 1.0;
constexpr double kMeasure_s = 2.0;

CalibrationSample Measure(const sim::TerrainWorld& flat, const sim::WorldOptions& options,
                          const controller::SkidSteerConfig& config,
                          const common::Twist2& command) {
  sim::Simulation simulation(flat, common::Pose2{}, options);
  auto step_for = [&](double seconds) {
    const int steps = static_cast<int>(std::lround(seconds / simulation.timestep()));
    for (int i = 0; i < steps; ++i) simulation.Step();
  };
  step_for(kSettle_s);
  simulation.SetWheelSpeedCommands(controller::ToWheelSpeeds(command, config));
  step_for(kSpinUp_s);

  // integrate the wrapped yaw increments and the forward displacement over the window
  const Eigen::Isometry3d X_start = simulation.State().X_WB;
  double turned = 0.0;
  double previous_yaw = common::ToRollPitchYaw(X_start.linear()).yaw;
  const int steps = static_cast<int>(std::lround(kMeasure_s / simulation.timestep()));
  for (int i = 0; i < steps; ++i) {
    simulation.Step();
    const double yaw = common::ToRollPitchYaw(simulation.State().X_WB.linear()).yaw;
    turned += common::WrapAngle(yaw - previous_yaw);
    previous_yaw = yaw;
  }
  const Eigen::Vector3d moved = simulation.State().X_WB.translation() - X_start.translation();
  CalibrationSample sample;
  sample.commanded_v_m_s = command.v;
  sample.commanded_omega_rad_s = command.omega;
  sample.measured_v_m_s = moved.dot(X_start.linear().col(0)) / kMeasure_s;
  sample.measured_omega_rad_s = turned / kMeasure_s;
  return sample;
}

}  // namespace

CalibrationResult CalibrateSkidSteer(const std::string& robot_model_path,
                                     const controller::SkidSteerConfig& config) {
  sim::TerrainConfig terrain;
  terrain.type = sim::TerrainType::kFlat;
  terrain.size_m = {30.0, 30.0};
  const sim::TerrainWorld flat = sim::GenerateTerrain(terrain);
  sim::WorldOptions options;
  options.robot_model_path = robot_model_path;

  CalibrationResult result;
  double ratio_sum = 0.0;
  int spins = 0;
  for (double omega : {0.5, 1.0, 2.0}) {
    result.samples.push_back(Measure(flat, options, config, {0.0, omega}));
    ratio_sum += omega / result.samples.back().measured_omega_rad_s;
    ++spins;
  }
  for (double v : {0.5, 1.0, 2.0})
    result.samples.push_back(Measure(flat, options, config, {v, 0.0}));
  result.effective_track_factor = config.effective_track_factor * ratio_sum / spins;
  return result;
}

void WriteCalibration(const CalibrationResult& result, const controller::SkidSteerConfig& used,
                      const OutputFolder& folder) {
  std::string csv = "commanded_v_m_s,commanded_omega_rad_s,measured_v_m_s,measured_omega_rad_s\n";
  nlohmann::json samples = nlohmann::json::array();
  for (const CalibrationSample& sample : result.samples) {
    fmt::format_to(std::back_inserter(csv), "{},{},{:.6f},{:.6f}\n", sample.commanded_v_m_s,
                   sample.commanded_omega_rad_s, sample.measured_v_m_s,
                   sample.measured_omega_rad_s);
    samples.push_back({{"commanded_v_m_s", sample.commanded_v_m_s},
                       {"commanded_omega_rad_s", sample.commanded_omega_rad_s},
                       {"measured_v_m_s", sample.measured_v_m_s},
                       {"measured_omega_rad_s", sample.measured_omega_rad_s}});
  }
  WriteTextFile(folder.File("calibration.csv"), csv);
  const nlohmann::json summary = {{"effective_track_factor_used", used.effective_track_factor},
                                  {"effective_track_factor", result.effective_track_factor},
                                  {"samples", samples}};
  WriteTextFile(folder.File("calibration.json"), summary.dump(2) + "\n");
}

}  // namespace trav::scenarios
