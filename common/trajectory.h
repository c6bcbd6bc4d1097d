#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/check.h"

namespace trav::common {

/// One state of a planar trajectory of the robot base in W.
struct TrajectoryPoint {
  double t_s{0.0};                                      ///< time [s]
  Eigen::Vector2d position_W{Eigen::Vector2d::Zero()};  ///< [m]
  double yaw{0.0};                                      ///< heading [rad], continuous (unwrapped)
  double v{0.0};                                        ///< forward speed [m/s]
  double omega{0.0};                                    ///< yaw rate [rad/s]
  double acceleration{0.0};                             ///< forward acceleration [m/s^2]
};

/// A time-parameterised planar trajectory given by dense samples (planners and reference generators
/// sample finely, 10 ms or less); sampling interpolates linearly between them and holds the end
/// points outside the time range.
class Trajectory {
 public:
  Trajectory() = default;
  /// @throws std::invalid_argument if `points` is empty or times do not strictly increase.
  explicit Trajectory(std::vector<TrajectoryPoint> points);

  /// The state at time t [s]. Precondition (checked): not empty.
  TrajectoryPoint Sample(double t_s) const;

  /// Times of the first and last samples [s]. Precondition (checked): not empty.
  double start_time() const {
    TRAV_DEMAND(!points_.empty());
    return points_.front().t_s;
  }
  double end_time() const {
    TRAV_DEMAND(!points_.empty());
    return points_.back().t_s;
  }
  bool empty() const { return points_.empty(); }
  const std::vector<TrajectoryPoint>& points() const { return points_; }

 private:
  std::vector<TrajectoryPoint> points_;
};

/// Builds a trajectory that follows the planar curve through `path_W` (dense points, at most a few
/// centimetres apart) at `speed` [m/s], starting and ending at rest with `acceleration` [m/s^2]
/// ramps, sampled every `dt_s` from t = 0. Yaw follows the curve's tangent (unwrapped), omega its
/// rate of change. @throws std::invalid_argument for fewer than 2 points or non-positive values.
Trajectory TrajectoryAlongPath(const std::vector<Eigen::Vector2d>& path_W, double speed,
                               double acceleration, double dt_s = 0.01);

}  // namespace trav::common
