#include "scenarios/open_loop_run.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "controller/skid_steer.h"
#include "renders/renderer.h"
#include "renders/video_writer.h"
#include "sim/simulation.h"

namespace trav::scenarios {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kTrajectoryPeriod_s = 0.02;

// The video camera for the scenario's camera mode.
class VideoCamera {
 public:
  VideoCamera(renders::CameraMode mode, const sim::TerrainWorld& world) : mode_(mode) {
    const Eigen::Vector2d centre = world.geometry.Center();
    overview_ = renders::OverviewView(
        Eigen::Vector3d(centre.x(), centre.y(), world.height_m.mean()), world.geometry.Extent());
  }
  renders::CameraView View(const Eigen::Isometry3d& X_WB, double dt_s) {
    switch (mode_) {
      case renders::CameraMode::kChase:
        return chase_.Update(X_WB, dt_s);
      case renders::CameraMode::kOverview:
        return overview_;
      case renders::CameraMode::kTopDown:
        return renders::TopDownView(X_WB.translation(), 8.0);
    }
    return overview_;
  }

 private:
  renders::CameraMode mode_;
  renders::ChaseCamera chase_;
  renders::CameraView overview_;
};

}  // namespace

std::string RobotModelPath(const Scenario& scenario, const std::string& models_dir) {
  const std::filesystem::path model(scenario.robot_model);
  return model.is_absolute() ? model.string()
                             : (std::filesystem::path(models_dir) / model).string();
}

RunSummary RunOpenLoop(const Scenario& scenario, const std::string& robot_model_path,
                       const std::string& output_dir, const ProgressCallback& progress) {
  const auto wall_start = std::chrono::steady_clock::now();
  const sim::TerrainWorld world =
      sim::GenerateTerrain(scenario.terrain, {scenario.start_W.position, scenario.goal_W});
  sim::WorldOptions options;
  options.robot_model_path = robot_model_path;
  options.timestep_s = scenario.physics_timestep_s;
  options.ground_friction = scenario.ground_friction;
  sim::Simulation simulation(world, scenario.start_W, options);

  // video: renderer and encoder only when asked for
  std::unique_ptr<renders::Renderer> renderer;
  std::unique_ptr<renders::VideoWriter> video;
  std::optional<VideoCamera> camera;
  renders::Image frame;
  if (scenario.video.enabled) {
    renderer = std::make_unique<renders::Renderer>(&simulation, scenario.video.render);
    video = std::make_unique<renders::VideoWriter>(
        output_dir + "/video.mp4", scenario.video.render.width, scenario.video.render.height,
        scenario.video.fps);
    camera.emplace(scenario.video.camera, world);
  }
  const double frame_period_s = 1.0 / scenario.video.fps;
  double next_frame_s = 0.0;
  const int steps_per_sample =
      std::max(1, static_cast<int>(std::lround(kTrajectoryPeriod_s / simulation.timestep())));

  std::ofstream trajectory(output_dir + "/trajectory.csv");
  trajectory << "t,x,y,z,roll,pitch,yaw,v_forward,yaw_rate,cmd_v,cmd_omega,"
                "wheel_fl,wheel_rl,wheel_fr,wheel_rr\n";

  RunSummary summary;
  const double dt = simulation.timestep();
  const int total_steps = static_cast<int>(std::ceil(scenario.duration_s / dt - 1e-9));
  const double tilt_limit = scenario.rollover_limit_deg / kRadToDeg;
  double sum_roll2 = 0.0;
  double sum_pitch2 = 0.0;
  common::RobotState state = simulation.State();
  Eigen::Vector2d last_xy = state.X_WB.translation().head<2>();
  int progress_step = 0;

  for (int step = 0; step < total_steps; ++step) {
    const common::Twist2 command = DriveCommandAt(scenario.drive, simulation.time());
    simulation.SetWheelSpeedCommands(controller::ToWheelSpeeds(command, scenario.skid_steer));

    if (video && simulation.time() >= next_frame_s - 1e-9) {
      renderer->Render(simulation, camera->View(state.X_WB, frame_period_s), {}, &frame);
      video->Write(frame);
      next_frame_s += frame_period_s;
    }

    const sim::StepStatus status = simulation.Step();
    ++summary.physics_steps;
    if (status == sim::StepStatus::kDiverged) {
      summary.outcome = Outcome::kDiverged;
      break;
    }
    state = simulation.State();
    const common::RollPitchYaw rpy = common::ToRollPitchYaw(state.X_WB.linear());
    summary.max_roll_deg = std::max(summary.max_roll_deg, std::abs(rpy.roll) * kRadToDeg);
    summary.max_pitch_deg = std::max(summary.max_pitch_deg, std::abs(rpy.pitch) * kRadToDeg);
    sum_roll2 += rpy.roll * rpy.roll;
    sum_pitch2 += rpy.pitch * rpy.pitch;
    const Eigen::Vector2d xy = state.X_WB.translation().head<2>();
    summary.distance_m += (xy - last_xy).norm();
    last_xy = xy;

    if ((step + 1) % steps_per_sample == 0) {
      const Eigen::Vector3d p = state.X_WB.translation();
      char line[512];
      std::snprintf(line, sizeof(line),
                    "%.3f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f\n",
                    state.time_s, p.x(), p.y(), p.z(), rpy.roll, rpy.pitch, rpy.yaw,
                    state.v_WB_B.x(), state.w_WB_B.z(), command.v, command.omega,
                    state.wheel_speeds[0], state.wheel_speeds[1], state.wheel_speeds[2],
                    state.wheel_speeds[3]);
      trajectory << line;
    }
    if (common::TiltAngle(state.X_WB.linear()) > tilt_limit) {
      summary.outcome = Outcome::kRolledOver;
      break;
    }
    if (progress && (step - progress_step) * dt >= 0.5) {
      progress_step = step;
      progress(static_cast<double>(step + 1) / total_steps);
    }
  }
  if (progress) progress(1.0);

  if (video) {
    video->Close();
    summary.video_frames = video->frames_written();
  }
  trajectory.close();
  if (!trajectory) throw std::runtime_error("cannot write " + output_dir + "/trajectory.csv");

  summary.sim_time_s = simulation.time();
  summary.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  summary.real_time_factor =
      summary.wall_time_s > 0.0 ? summary.sim_time_s / summary.wall_time_s : 0.0;
  const double n = std::max(1, summary.physics_steps);
  summary.rms_roll_deg = std::sqrt(sum_roll2 / n) * kRadToDeg;
  summary.rms_pitch_deg = std::sqrt(sum_pitch2 / n) * kRadToDeg;
  summary.final_pose_W.position = state.X_WB.translation().head<2>();
  summary.final_pose_W.yaw = common::ToRollPitchYaw(state.X_WB.linear()).yaw;
  summary.final_pose_W.time_s = state.time_s;
  summary.mujoco_warning_count = simulation.warning_count();
  summary.mujoco_warnings = simulation.warnings();
  return summary;
}

std::string SummaryJson(const Scenario& scenario, const RunSummary& summary) {
  nlohmann::json json;
  json["scenario"] = scenario.name;
  json["outcome"] = OutcomeName(summary.outcome);
  json["expected_outcome"] = OutcomeName(scenario.expected_outcome);
  json["terrain"] = {{"type", sim::TerrainTypeName(scenario.terrain.type)},
                     {"seed", scenario.terrain.seed}};
  json["sim_time_s"] = summary.sim_time_s;
  json["wall_time_s"] = summary.wall_time_s;
  json["real_time_factor"] = summary.real_time_factor;
  json["distance_m"] = summary.distance_m;
  json["max_roll_deg"] = summary.max_roll_deg;
  json["max_pitch_deg"] = summary.max_pitch_deg;
  json["rms_roll_deg"] = summary.rms_roll_deg;
  json["rms_pitch_deg"] = summary.rms_pitch_deg;
  json["final_pose"] = {{"x", summary.final_pose_W.position.x()},
                        {"y", summary.final_pose_W.position.y()},
                        {"yaw", summary.final_pose_W.yaw}};
  json["physics_steps"] = summary.physics_steps;
  json["mujoco_warning_count"] = summary.mujoco_warning_count;
  json["mujoco_warnings"] = summary.mujoco_warnings;
  json["video"] = summary.video_frames > 0 ? nlohmann::json("video.mp4") : nlohmann::json(nullptr);
  json["video_frames"] = summary.video_frames;
  return json.dump(2) + "\n";
}

}  // namespace trav::scenarios
