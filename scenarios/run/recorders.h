#pragma once

#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "scenarios/run/closed_loop.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios {

/// A perceived mover farther than this from every true mover is a false mover [m].
constexpr double kFalseMoverDistance_m = 1.0;

/// Physics steps between two rows of trajectory.csv (50 Hz) for a physics timestep.
int StepsPerTrajectorySample(double timestep_s);

/// True if trajectory.csv samples step `index` (every 20 ms of simulation time).
bool TrajectorySampleDue(const ClosedLoop& loop, int index);

/// The time series (timeseries.csv, the driven path, the plan in videos) are sampled every this
/// many rows of trajectory.csv (10 Hz).
constexpr int kTrajectorySamplesPerTimeSeriesSample = 5;

/// True if the closed loop's time series samples step `index` (every 0.1 s of simulation time).
bool TimeSeriesSampleDue(const ClosedLoop& loop, int index);

/// Writes trajectory.csv: the true state and command at 50 Hz.
class TrajectoryRecorder : public LoopObserver {
 public:
  /// Opens `<output_dir>/trajectory.csv`.
  explicit TrajectoryRecorder(const std::string& output_dir);

  void OnPhysicsStep(const ClosedLoop& loop, const LoopStep& step) override;
  /// Closes the file. @throws common::InputError if it could not be written whole.
  void OnEnd(const ClosedLoop& loop, Outcome outcome) override;

 private:
  std::string path_;
  std::ofstream file_;
};

/// Writes timeseries.csv in mode navigate: state, command, goal distance, map error and the wall
/// time of each module since the previous row, at 10 Hz.
class TimeSeriesRecorder : public LoopObserver {
 public:
  /// Opens `<output_dir>/timeseries.csv`.
  explicit TimeSeriesRecorder(const std::string& output_dir);

  void OnStepChecked(const ClosedLoop& loop, const LoopStep& step) override;
  /// Closes the file. @throws common::InputError if it could not be written whole.
  void OnEnd(const ClosedLoop& loop, Outcome outcome) override;

 private:
  std::string path_;
  std::ofstream file_;
  std::map<std::string, double> module_totals_ms_;
};

/// Writes imu.csv: every IMU sample (scenario section `imu`), measured and true, in the IMU frame.
class ImuRecorder : public LoopObserver {
 public:
  /// Opens `<output_dir>/imu.csv`.
  explicit ImuRecorder(const std::string& output_dir);

  void OnPhysicsStep(const ClosedLoop& loop, const LoopStep& step) override;
  /// Closes the file. @throws common::InputError if it could not be written whole.
  void OnEnd(const ClosedLoop& loop, Outcome outcome) override;

 private:
  std::string path_;
  std::ofstream file_;
};

/// Writes every LiDAR frame as clouds/frame_NNNNNN.pcd.
class CloudRecorder : public LoopObserver {
 public:
  /// Creates `<output_dir>/clouds`.
  explicit CloudRecorder(const std::string& output_dir);

  void OnLidarFrame(const ClosedLoop& loop, const lidar::LidarFrame& frame,
                    const Eigen::Matrix3Xf& points_W) override;

 private:
  std::string folder_;
};

/// The robot's motion over a run: distance, roll and pitch, vertical acceleration.
class MotionStatistics : public LoopObserver {
 public:
  /// Statistics from the robot's position at the start.
  explicit MotionStatistics(const Eigen::Vector2d& start_W) : last_xy_(start_W) {}

  void OnPhysicsStep(const ClosedLoop& loop, const LoopStep& step) override;
  void OnStepChecked(const ClosedLoop& loop, const LoopStep& step) override;

  double distance_m() const { return distance_m_; }
  double max_roll_deg() const { return max_roll_deg_; }
  double max_pitch_deg() const { return max_pitch_deg_; }
  /// RMS over `steps` physics steps [deg].
  double rms_roll_deg(int steps) const;
  double rms_pitch_deg(int steps) const;
  /// RMS of the vertical acceleration over the steps after the first [m/s^2].
  double rms_vertical_acceleration_m_s2(int steps) const;

 private:
  Eigen::Vector2d last_xy_;
  double distance_m_{0.0};
  double max_roll_deg_{0.0};
  double max_pitch_deg_{0.0};
  double sum_roll2_{0.0};
  double sum_pitch2_{0.0};
  double sum_vertical_acceleration2_{0.0};
};

/// How far the pose estimate strays from the truth over a run (compared when each command is
/// decided, the estimate and the state being of the same time): the largest error, and the poses
/// every 0.1 m driven for the relative pose error over 10 m.
class LocalizationError : public LoopObserver {
 public:
  void OnCommand(const ClosedLoop& loop) override;

  /// The errors of `estimate` against `truth` (the run's last), the largest seen and the relative
  /// errors; the method is left for the caller.
  LocalizationMetrics Metrics(const common::RobotState& estimate,
                              const common::RobotState& truth) const;

 private:
  double max_position_error_m_{0.0};
  double distance_m_{0.0};
  std::optional<Eigen::Vector3d> last_p_W_;
  std::vector<PoseSample> samples_;
};

/// How the robot and the movers met (mode navigate): the closest gap, near misses, and how well
/// the perceived movers matched the true ones.
class MoverEncounters : public LoopObserver {
 public:
  MoverEncounters(double robot_radius_m, double near_miss_clearance_m)
      : robot_radius_m_(robot_radius_m), near_miss_clearance_m_(near_miss_clearance_m) {}

  void OnCommand(const ClosedLoop& loop) override;

  /// Smallest gap between the robot's disc and a mover's footprint (infinite: no movers) [m].
  double min_clearance_m() const { return min_clearance_m_; }
  int near_misses() const { return near_misses_; }
  /// Mean distance from a perceived mover to the nearest true one, over the samples within
  /// kFalseMoverDistance_m [m] (0 without samples), their count, and the false movers.
  double tracking_error_m() const;
  int perceived_samples() const { return tracking_error_count_; }
  int false_mover_samples() const { return false_mover_samples_; }

 private:
  double robot_radius_m_;
  double near_miss_clearance_m_;
  std::vector<bool> near_miss_;  // per mover: within the near-miss clearance now
  double min_clearance_m_{std::numeric_limits<double>::infinity()};
  int near_misses_{0};
  double tracking_error_sum_{0.0};
  int tracking_error_count_{0};
  int false_mover_samples_{0};
};

/// The path the robot drove, sampled at 10 Hz from the start to the end (mode navigate).
class DrivenPath : public LoopObserver {
 public:
  explicit DrivenPath(const Eigen::Vector2d& start_W) : points_W_{start_W} {}

  void OnStepChecked(const ClosedLoop& loop, const LoopStep& step) override;
  void OnEnd(const ClosedLoop& loop, Outcome outcome) override;

  const std::vector<Eigen::Vector2d>& points_W() const { return points_W_; }

 private:
  std::vector<Eigen::Vector2d> points_W_;
};

}  // namespace trav::scenarios
