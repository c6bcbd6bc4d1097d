// trav calibrate: the skid-steer mapping of the scenario's robot measured on flat ground.
#include <cstdio>
#include <memory>
#include <string>

#include "scenarios/cli/cli.h"
#include "scenarios/run/calibration.h"
#include "scenarios/run/output_folder.h"

namespace trav::scenarios::cli {
namespace {

int Calibrate(const ScenarioOptions& options) {
  const Scenario scenario = ResolveScenario(options, std::nullopt);
  const std::string model = ExistingRobotModel(scenario);
  const CalibrationResult result = CalibrateSkidSteer(model, scenario.skid_steer);
  std::printf("skid-steer calibration of %s on flat ground (effective_track_factor %.3f)\n",
              model.c_str(), scenario.skid_steer.effective_track_factor);
  std::printf("%12s %14s %12s %14s\n", "cmd v [m/s]", "cmd w [rad/s]", "v [m/s]", "w [rad/s]");
  for (const CalibrationSample& sample : result.samples) {
    std::printf("%12.2f %14.2f %12.3f %14.3f\n", sample.commanded_v_m_s,
                sample.commanded_omega_rad_s, sample.measured_v_m_s, sample.measured_omega_rad_s);
  }
  std::printf("effective_track_factor that matches the commanded yaw rates: %.3f\n",
              result.effective_track_factor);
  if (options.out) {
    OutputFolder folder(scenario.output_dir, "calibrate", options.overwrite);
    WriteCalibration(result, scenario.skid_steer, folder);
    folder.Commit();
    std::printf("written to %s (calibration.csv, calibration.json)\n", folder.final_path().c_str());
  }
  return kExitExpected;
}

}  // namespace

Command AddCalibrateCommand(CLI::App* app) {
  auto options = std::make_shared<ScenarioOptions>();
  CLI::App* calibrate = app->add_subcommand(
      "calibrate", "Measure the skid-steer mapping of the scenario's robot on flat ground");
  AddScenarioOptions(calibrate, options.get());
  return {calibrate, [options] { return Calibrate(*options); }};
}

}  // namespace trav::scenarios::cli
