#pragma once

#include <memory>
#include <optional>

#include <Eigen/Geometry>

#include "common/archive.h"

namespace trav::mapping {

/// Settings of the LiDAR odometry (scenario section `localization`, method scan-matching).
struct LidarOdometryConfig {
  double scan_voxel_m{0.4};   ///< each scan is thinned to one point per voxel before matching [m]
  double map_voxel_m{0.4};    ///< the local map keeps one point per voxel [m]
  double min_range_m{1.0};    ///< closer points (the robot's own surroundings) are not matched [m]
  double max_range_m{25.0};   ///< farther points are not matched [m]
  double map_radius_m{25.0};  ///< the local map keeps the points within this of the sensor [m]
  /// The map takes a scan when the sensor has moved this far or turned by map_turn_rad since the
  /// last one it took [m].
  double map_step_m{0.5};
  double map_turn_rad{0.1};
  int max_iterations{30};  ///< GICP iterations per scan (a cap, never a time budget)
  /// A registration that moves the pose farther than this from the prediction is rejected (the
  /// prediction is kept): a scan slid along a plane or onto a mover [m], [rad].
  double max_correction_m{0.3};
  double max_correction_rad{0.1};
  double max_correspondence_m{1.0};  ///< point pairs farther apart are not matched [m]

  /// The scan-matching keys of scenario section `localization` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("scan_voxel", &scan_voxel_m, {0.05, 5});
    a->Field("map_voxel", &map_voxel_m, {0.05, 5});
    a->Field("min_range", &min_range_m, {0, 100});
    a->Field("max_range", &max_range_m, {0.5, 500});
    a->Field("map_radius", &map_radius_m, {1, 500});
    a->Field("map_step", &map_step_m, {0, 100});
    a->Field("map_turn", &map_turn_rad, {0, 3.15});
    a->Field("max_iterations", &max_iterations, {1, 1000});
    a->Field("max_correction", &max_correction_m, {0.01, 100});
    a->Field("max_correction_angle", &max_correction_rad, {0.001, 3.15});
    a->Field("max_correspondence", &max_correspondence_m, {0.01, 100});
  }
};

/// Checks a config. @throws common::InputError naming the key (relative: "max_range") and value.
void ValidateLidarOdometryConfig(const LidarOdometryConfig& config);

/// A LiDAR odometry: each scan de-skewed with the predicted motion over the scan interval (the
/// previous interval's translation, constant velocity, and the gyroscope's rotation when given,
/// else the previous interval's; each point moved from the sensor pose at its own time to the pose
/// at the scan's end), thinned, and registered with PCL's generalized ICP against a local map of
/// the earlier registered scans, starting from that prediction (a registration that strays too far
/// from it, or a scan or map too small to match, keeps the prediction). Its poses are
/// the sensor's, L, in the odometry frame O, which is where the sensor started. Deterministic:
/// iteration caps, no threads.
class LidarOdometry {
 public:
  /// Starts at X_OL_start (the sensor's pose when the first scan ends).
  LidarOdometry(const LidarOdometryConfig& config, const Eigen::Isometry3d& X_OL_start);
  ~LidarOdometry();
  LidarOdometry(const LidarOdometry&) = delete;
  LidarOdometry& operator=(const LidarOdometry&) = delete;

  /// Registers one scan: `points_L` in the sensor frame at each point's own time, `time_offsets_s`
  /// after the scan's start, the scan lasting `scan_period_s`; `R_turn` is the sensor's rotation
  /// over the scan interval (the previous scan's end to this one's, R_{L(k-1) L(k)}) from a
  /// gyroscope, if there is one: it replaces the constant-velocity rotation in the prediction and
  /// the de-skewing. Returns X_OL at the scan's end. The first scan only starts the map.
  const Eigen::Isometry3d& AddScan(const Eigen::Matrix3Xf& points_L,
                                   const Eigen::VectorXf& time_offsets_s, double scan_period_s,
                                   const std::optional<Eigen::Matrix3d>& R_turn = std::nullopt);

  /// The sensor's pose at the end of the last scan.
  const Eigen::Isometry3d& X_OL() const { return X_OL_; }

  /// Whether the registration of the last scan was accepted: it converged within the correction
  /// limits (false before one; a scan not accepted keeps the constant-velocity prediction).
  bool last_accepted() const { return last_accepted_; }
  /// Scans whose registration was not accepted so far.
  int rejected_scans() const { return rejected_scans_; }
  /// Points in the local map.
  int map_points() const;

 private:
  struct Impl;
  LidarOdometryConfig config_;
  std::unique_ptr<Impl> impl_;
  Eigen::Isometry3d X_OL_;
  Eigen::Isometry3d motion_;  // the last scan interval's motion, X_{L(k-1) L(k)}
  Eigen::Isometry3d X_OL_last_map_;
  int scans_{0};
  bool last_accepted_{false};
  int rejected_scans_{0};
};

}  // namespace trav::mapping
