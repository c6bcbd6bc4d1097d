#pragma once

#include <functional>
#include <string>
#include <vector>

#include "common/pose.h"
#include "scenarios/scenario.h"

namespace trav::scenarios {

/// What `trav run` reports in summary.json.
struct RunSummary {
  Outcome outcome{Outcome::kCompleted};
  double sim_time_s{0.0};
  double wall_time_s{0.0};
  double real_time_factor{0.0};  ///< simulated seconds per wall-clock second
  double distance_m{0.0};        ///< horizontal path length of the base
  double max_roll_deg{0.0};      ///< largest |roll|
  double max_pitch_deg{0.0};     ///< largest |pitch|
  double rms_roll_deg{0.0};
  double rms_pitch_deg{0.0};
  common::Pose2 final_pose_W{};
  int physics_steps{0};
  int mujoco_warning_count{0};
  std::vector<std::string> mujoco_warnings;
  int video_frames{0};  ///< 0 when video is off
};

/// Progress reports: fraction of the scenario's duration simulated so far, in [0, 1].
using ProgressCallback = std::function<void(double fraction)>;

/// Runs a scenario open loop: generates its terrain, builds the MuJoCo world, drives the robot by
/// the scenario's script through the skid-steer mapping, and writes into `output_dir` (which must
/// exist) `trajectory.csv` (50 Hz) and, if video is on, `video.mp4`. Stops early on rollover or
/// divergence (recorded as the outcome).
/// @throws common::InputError on bad input (an unreadable robot model); std::runtime_error if
/// video was asked for and GL or ffmpeg is missing.
RunSummary RunOpenLoop(const Scenario& scenario, const std::string& robot_model_path,
                       const std::string& output_dir, const ProgressCallback& progress = {});

/// Absolute path of the robot model of `scenario` (robot.model in `models_dir` unless absolute).
std::string RobotModelPath(const Scenario& scenario, const std::string& models_dir);

/// summary.json text of a run.
std::string SummaryJson(const Scenario& scenario, const RunSummary& summary);

}  // namespace trav::scenarios
