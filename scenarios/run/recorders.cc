#include "scenarios/run/recorders.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>

#include <fmt/format.h>

#include "scenarios/run/output_folder.h"
#include "scenarios/run/pcd_io.h"

namespace trav::scenarios {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kTrajectoryPeriod_s = 0.02;

}  // namespace

int StepsPerTrajectorySample(double timestep_s) {
  return std::max(1, static_cast<int>(std::lround(kTrajectoryPeriod_s / timestep_s)));
}

bool TrajectorySampleDue(const ClosedLoop& loop, int index) {
  return (index + 1) % StepsPerTrajectorySample(loop.timestep_s()) == 0;
}

bool TimeSeriesSampleDue(const ClosedLoop& loop, int index) {
  const int period =
      kTrajectorySamplesPerTimeSeriesSample * StepsPerTrajectorySample(loop.timestep_s());
  return (index + 1) % period == 0;
}

TrajectoryRecorder::TrajectoryRecorder(const std::string& output_dir)
    : path_(output_dir + "/trajectory.csv"), file_(path_) {
  file_ << "t,x,y,z,roll,pitch,yaw,v_forward,yaw_rate,cmd_v,cmd_omega,"
           "wheel_fl,wheel_rl,wheel_fr,wheel_rr\n";
}

void TrajectoryRecorder::OnPhysicsStep(const ClosedLoop& loop, const LoopStep& step) {
  if (!TrajectorySampleDue(loop, step.index)) return;
  const common::RobotState& state = step.state;
  const Eigen::Vector3d p = state.X_WB.translation();
  fmt::memory_buffer line;
  fmt::format_to(
      std::back_inserter(line),
      "{:.3f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.4f},{:.4f},{:.3f},{:.3f},{:.3f},"
      "{:.3f},{:.3f},{:.3f}\n",
      state.time_s, p.x(), p.y(), p.z(), step.rpy.roll, step.rpy.pitch, step.rpy.yaw,
      state.v_WB_B.x(), state.w_WB_B.z(), step.command.v, step.command.omega, state.wheel_speeds[0],
      state.wheel_speeds[1], state.wheel_speeds[2], state.wheel_speeds[3]);
  file_.write(line.data(), static_cast<std::streamsize>(line.size()));
}

void TrajectoryRecorder::OnEnd(const ClosedLoop& /*loop*/, Outcome /*outcome*/) {
  file_.close();
  CheckWritten(path_, !file_.fail());
}

ImuRecorder::ImuRecorder(const std::string& output_dir)
    : path_(output_dir + "/imu.csv"), file_(path_) {
  file_ << "t,accel_x,accel_y,accel_z,gyro_x,gyro_y,gyro_z,true_accel_x,true_accel_y,"
           "true_accel_z,true_gyro_x,true_gyro_y,true_gyro_z\n";
}

void ImuRecorder::OnPhysicsStep(const ClosedLoop& loop, const LoopStep& /*step*/) {
  if (loop.imu() == nullptr) return;
  fmt::memory_buffer line;
  for (const sim::ImuSample& sample : loop.imu()->samples()) {
    fmt::format_to(std::back_inserter(line), "{:.3f}", sample.t_s);
    for (const sim::ImuMeasurement* m : {&sample.measured, &sample.truth}) {
      fmt::format_to(std::back_inserter(line), ",{:.5f},{:.5f},{:.5f},{:.6f},{:.6f},{:.6f}",
                     m->accel_I.x(), m->accel_I.y(), m->accel_I.z(), m->gyro_I.x(), m->gyro_I.y(),
                     m->gyro_I.z());
    }
    line.push_back('\n');
  }
  file_.write(line.data(), static_cast<std::streamsize>(line.size()));
}

void ImuRecorder::OnEnd(const ClosedLoop& /*loop*/, Outcome /*outcome*/) {
  file_.close();
  CheckWritten(path_, !file_.fail());
}

void LocalizationError::OnCommand(const ClosedLoop& loop) {
  const Eigen::Isometry3d& X_WB = loop.state().X_WB;
  const Eigen::Isometry3d& X_OB = loop.estimate().X_WB;
  max_position_error_m_ =
      std::max(max_position_error_m_, (X_OB.translation() - X_WB.translation()).head<2>().norm());
  if (last_p_W_) distance_m_ += (X_WB.translation() - *last_p_W_).head<2>().norm();
  last_p_W_ = X_WB.translation();
  constexpr double kSampleSpacing_m = 0.1;
  if (samples_.empty() || distance_m_ - samples_.back().distance_m >= kSampleSpacing_m) {
    samples_.push_back({distance_m_, X_WB, X_OB});
  }
}

LocalizationMetrics LocalizationError::Metrics(const common::RobotState& estimate,
                                               const common::RobotState& truth) const {
  LocalizationMetrics metrics;
  const Eigen::Vector3d error = estimate.X_WB.translation() - truth.X_WB.translation();
  metrics.final_position_error_m = error.head<2>().norm();
  metrics.final_z_error_m = error.z();
  const Eigen::Matrix3d R_error = estimate.X_WB.linear() * truth.X_WB.linear().transpose();
  metrics.final_yaw_error_deg = std::atan2(R_error(1, 0), R_error(0, 0)) * kRadToDeg;
  metrics.max_position_error_m = std::max(max_position_error_m_, metrics.final_position_error_m);
  const RelativePoseError relative = RelativePoseErrorOver(samples_, 10.0);
  metrics.relative_error_10m_m = relative.translation_m;
  metrics.relative_yaw_error_10m_deg = relative.yaw_deg;
  metrics.relative_error_stretches = relative.stretches;
  return metrics;
}

TimeSeriesRecorder::TimeSeriesRecorder(const std::string& output_dir)
    : path_(output_dir + "/timeseries.csv"), file_(path_) {
  file_ << "t,x,y,yaw,v_forward,yaw_rate,roll_deg,pitch_deg,vertical_acceleration,cmd_v,"
           "cmd_omega,goal_distance,mapping_error,lidar_ms,mapping_ms,planning_ms,control_ms,"
           "physics_ms,render_ms\n";
}

void TimeSeriesRecorder::OnStepChecked(const ClosedLoop& loop, const LoopStep& step) {
  if (!TimeSeriesSampleDue(loop, step.index)) return;
  const common::RobotState& state = step.state;
  const Eigen::Vector2d xy = state.X_WB.translation().head<2>();
  fmt::memory_buffer line;
  fmt::format_to(
      std::back_inserter(line),
      "{:.3f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.3f},{:.3f},{:.4f},{:.3f},{:.3f},{:.4f},"
      "{:.5f}",
      state.time_s, xy.x(), xy.y(), step.rpy.yaw, state.v_WB_B.x(), state.w_WB_B.z(),
      step.rpy.roll * kRadToDeg, step.rpy.pitch * kRadToDeg, step.vertical_acceleration_m_s2,
      step.command.v, step.command.omega, (xy - loop.scenario().goal_W).norm(),
      loop.last_mapping_error());
  // wall time of each module since the previous row [ms]
  for (const char* module : kTimedModules) {
    const double total = loop.times().Total(module);
    fmt::format_to(std::back_inserter(line), ",{:.3f}", total - module_totals_ms_[module]);
    module_totals_ms_[module] = total;
  }
  line.push_back('\n');
  file_.write(line.data(), static_cast<std::streamsize>(line.size()));
}

void TimeSeriesRecorder::OnEnd(const ClosedLoop& /*loop*/, Outcome /*outcome*/) {
  file_.close();
  CheckWritten(path_, !file_.fail());
}

CloudRecorder::CloudRecorder(const std::string& output_dir) : folder_(output_dir + "/clouds") {
  std::filesystem::create_directories(folder_);
}

void CloudRecorder::OnLidarFrame(const ClosedLoop& /*loop*/, const lidar::LidarFrame& frame,
                                 const Eigen::Matrix3Xf& /*points_W*/) {
  WriteLidarFramePcd(fmt::format("{}/frame_{:06}.pcd", folder_, frame.index), frame);
}

void MotionStatistics::OnPhysicsStep(const ClosedLoop& /*loop*/, const LoopStep& step) {
  max_roll_deg_ = std::max(max_roll_deg_, std::abs(step.rpy.roll) * kRadToDeg);
  max_pitch_deg_ = std::max(max_pitch_deg_, std::abs(step.rpy.pitch) * kRadToDeg);
  sum_roll2_ += step.rpy.roll * step.rpy.roll;
  sum_pitch2_ += step.rpy.pitch * step.rpy.pitch;
  const Eigen::Vector2d xy = step.state.X_WB.translation().head<2>();
  distance_m_ += (xy - last_xy_).norm();
  last_xy_ = xy;
}

void MotionStatistics::OnStepChecked(const ClosedLoop& /*loop*/, const LoopStep& step) {
  if (step.index > 0) {
    sum_vertical_acceleration2_ +=
        step.vertical_acceleration_m_s2 * step.vertical_acceleration_m_s2;
  }
}

double MotionStatistics::rms_roll_deg(int steps) const {
  return std::sqrt(sum_roll2_ / std::max(1, steps)) * kRadToDeg;
}

double MotionStatistics::rms_pitch_deg(int steps) const {
  return std::sqrt(sum_pitch2_ / std::max(1, steps)) * kRadToDeg;
}

double MotionStatistics::rms_vertical_acceleration_m_s2(int steps) const {
  return std::sqrt(sum_vertical_acceleration2_ / std::max(1, steps - 1));
}

void MoverEncounters::OnCommand(const ClosedLoop& loop) {
  const std::vector<planner::MovingObstacle>& true_movers = loop.true_movers();
  const Eigen::Vector2d robot_W = loop.state().X_WB.translation().head<2>();
  near_miss_.resize(true_movers.size(), false);
  for (std::size_t k = 0; k < true_movers.size(); ++k) {
    const planner::MovingObstacle& mover = true_movers[k];
    const double gap = (mover.position_W - robot_W).norm() - mover.radius_m - robot_radius_m_;
    min_clearance_m_ = std::min(min_clearance_m_, gap);
    if (!near_miss_[k] && gap < near_miss_clearance_m_) {
      near_miss_[k] = true;
      ++near_misses_;
    } else if (near_miss_[k] && gap > near_miss_clearance_m_ + 0.1) {
      near_miss_[k] = false;
    }
  }
  if (!loop.perceives_movers()) return;
  // each perceived mover against the nearest true one, now
  const double now_s = loop.simulation().time();
  for (const planner::MovingObstacle& seen : loop.predicted_movers()) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const planner::MovingObstacle& mover : true_movers) {
      nearest = std::min(nearest, (seen.PositionAt(now_s) - mover.position_W).norm());
    }
    if (nearest <= kFalseMoverDistance_m) {
      tracking_error_sum_ += nearest;
      ++tracking_error_count_;
    } else {
      ++false_mover_samples_;
    }
  }
}

double MoverEncounters::tracking_error_m() const {
  return tracking_error_count_ > 0 ? tracking_error_sum_ / tracking_error_count_ : 0.0;
}

void DrivenPath::OnStepChecked(const ClosedLoop& loop, const LoopStep& step) {
  if (TimeSeriesSampleDue(loop, step.index)) {
    points_W_.push_back(step.state.X_WB.translation().head<2>());
  }
}

void DrivenPath::OnEnd(const ClosedLoop& loop, Outcome /*outcome*/) {
  points_W_.push_back(loop.state().X_WB.translation().head<2>());
}

}  // namespace trav::scenarios
