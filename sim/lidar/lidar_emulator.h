#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "common/point_cloud.h"
#include "common/random.h"
#include "sim/lidar/lidar_config.h"
#include "sim/lidar/ray_scene.h"
#include "sim/lidar/scan_pattern.h"

namespace trav::lidar {

/// Counts of rays that produced no point in a frame.
struct DropCounts {
  int miss{0};      ///< nothing within range_max
  int blind{0};     ///< first surface closer than range_min (the blind zone)
  int dropout{0};   ///< random dropout
  int occluded{0};  ///< inside an occluded azimuth sector
  int weak{0};      ///< echo too weak: a dark or grazing surface beyond its detection range
};

/// One complete LiDAR frame.
struct LidarFrame {
  /// Points in the sensor frame L at each point's own time (what a real sensor reports), with per-
  /// point time offsets after `stamp_s` [s], line ids, reflectivity and tags (Livox's fields).
  common::PointCloud points_L;
  std::int64_t index{0};  ///< frame number since the sensor started
  int rays{0};            ///< rays fired in the frame
  DropCounts dropped{};
  /// Sensor poses X_WL from which the rays were cast, one per cast batch (physics step), with the
  /// time [s] each batch began; the first is the frame-start pose, the last the pose of the final
  /// batch.
  std::vector<Eigen::Isometry3d> batch_poses_W;
  std::vector<double> batch_times_s;
  Eigen::Isometry3d X_WL_end{Eigen::Isometry3d::Identity()};  ///< sensor pose at the frame's end

  const Eigen::Isometry3d& X_WL_start() const { return batch_poses_W.front(); }

  /// Sensor pose with which point `i` was measured (the pose of its batch).
  const Eigen::Isometry3d& PoseOfPoint(Eigen::Index i) const;
};

/// Points of a frame in W, each placed with the pose it was measured from (motion-corrected).
Eigen::Matrix3Xf PointsInWorld(const LidarFrame& frame);

/// The chance that a surface returns an echo (LidarConfig::detection): a logistic step at the
/// reach R = range_at_10_percent (c / 0.1)^k of the effective reflectance c (diffuse reflectance
/// times cos(incidence)), 5 % of R wide.
class DetectionModel {
 public:
  explicit DetectionModel(const LidarConfig& config);

  /// The chance of an echo from `range_m` off a surface of effective reflectance
  /// `effective_reflectance`; 1 when detection is off.
  double Probability(double effective_reflectance, double range_m) const;

 private:
  // Effective reflectances in [0, 1] fall in kBins bins of equal width.
  static constexpr int kBins = 64;

  bool enabled_{true};
  double range_at_10_percent_m_{0.0};
  double exponent_{0.0};  // k
  // Per bin, a range below which an echo is certain: less than half the reach at the bin's lower
  // edge (the reach grows with reflectance), where the logistic's argument is below -40 and the
  // probability rounds to exactly 1. Spares almost every ray the pow and exp of the formula, with
  // the same result to the bit.
  std::array<double, kBins> certain_range_m_{};
};

/// Emulates a scanning LiDAR over a RayScene: the caller advances time in batches (one per physics
/// step) with the sensor pose of that batch; the rays whose time stamps fall in the batch are cast
/// from that pose, so motion distortion is real. Noise, dropout and occlusion are seeded: the same
/// config and the same poses give bit-identical frames. After the first frame nothing is allocated.
class LidarEmulator {
 public:
  /// @throws common::InputError for an invalid config or an unreadable scan table.
  explicit LidarEmulator(const LidarConfig& config);

  /// Casts the rays with time stamps in [t_begin_s, t_end_s) from X_WL (sensor pose in W).
  void Scan(const RayScene& scene, double t_begin_s, double t_end_s, const Eigen::Isometry3d& X_WL);

  /// True when a frame is complete and not yet taken.
  bool frame_ready() const { return ready_; }

  /// Moves the complete frame into `frame` (swapping buffers: no allocation in steady use).
  /// Precondition (checked): frame_ready().
  void TakeFrame(LidarFrame* frame);

  const LidarConfig& config() const { return config_; }

  /// Rays per frame.
  int rays_per_frame() const { return rays_per_frame_; }

  /// The number of rays fired before time `t_s` (ray i fires at i / points_per_second): Scan up
  /// to t_s completes frame k once this reaches (k + 1) rays_per_frame().
  std::int64_t RaysBefore(double t_s) const;

 private:
  void StartFrame(std::int64_t index, const Eigen::Isometry3d& X_WL, double t_s);
  void FinishFrame(const Eigen::Isometry3d& X_WL);
  bool Occluded(float azimuth_rad) const;

  LidarConfig config_;
  std::shared_ptr<const ScanPattern> pattern_;  // the shipped table is shared by all emulators
  common::Random random_;
  int rays_per_frame_{0};
  std::int64_t next_ray_{0};  // global index of the next ray to fire
  LidarFrame building_;       // the frame being filled
  LidarFrame complete_;       // the last complete frame
  bool ready_{false};
  Eigen::Index filled_{0};                     // points in building_
  std::vector<float> occluded_sector_starts_;  // [rad], this frame
  // per batch scratch
  Eigen::Matrix3Xf pattern_directions_L_;
  Eigen::VectorXi pattern_lines_;
  Eigen::Matrix3Xf directions_W_;
  Eigen::Matrix3Xf directions_L_;
  Eigen::VectorXi lines_;
  Eigen::VectorXf times_;
  RayHits hits_;
  DetectionModel detection_;
};

}  // namespace trav::lidar
