// trav scan: N LiDAR frames of a scenario's drive as PCD files.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "common/input_error.h"
#include "scenarios/cli/cli.h"

namespace trav::scenarios::cli {
namespace {

int Scan(const ScenarioOptions& options, int frames) {
  if (!options.out) throw common::InputError("--out", "", "trav scan needs --out DIR");
  if (frames < 1) throw common::InputError("--frames", std::to_string(frames), "must be >= 1");
  Scenario scenario = ResolveScenario(options, false);
  if (!scenario.lidar.enabled)
    throw common::InputError("lidar.enabled", "false", "trav scan needs the LiDAR");
  // run long enough for the frames, whatever the scenario's duration
  scenario.duration_s = std::max(scenario.duration_s, (frames + 1) * scenario.lidar.frame_period_s);
  RunOptions run_options;
  run_options.record_clouds = true;
  run_options.max_lidar_frames = frames;
  const RunSummary summary = RunInFolder(scenario, run_options, options.overwrite);
  std::printf(
      "%d frames of %.0f points on average written to %s/clouds (PCD: x y z in the sensor frame, "
      "time, line)\n",
      summary.lidar_frames, summary.lidar_points_per_frame, scenario.output_dir.c_str());
  return summary.outcome == Outcome::kCompleted ? kExitExpected : kExitOtherOutcome;
}

}  // namespace

Command AddScanCommand(CLI::App* app) {
  auto options = std::make_shared<ScenarioOptions>();
  auto frames = std::make_shared<int>(10);
  CLI::App* scan = app->add_subcommand(
      "scan", "Drive the scenario's robot and write N LiDAR frames as PCD (no video)");
  AddScenarioOptions(scan, options.get());
  scan->add_option("--frames", *frames, "Number of frames to write")->capture_default_str();
  return {scan, [options, frames] { return Scan(*options, *frames); }};
}

}  // namespace trav::scenarios::cli
