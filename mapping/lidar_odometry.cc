#include "mapping/lidar_odometry.h"

#include <cmath>

#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>

#include "common/input_error.h"

// PCL's generalized ICP (Segal et al. 2009) does the registration: a maintained implementation of
// plane-to-plane ICP with its own kd-tree and optimiser. What is ours is the odometry around it:
// de-skewing, thinning, the local map and the constant-velocity prediction.
namespace trav::mapping {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// One point per voxel (PCL's voxel centroids).
Cloud::Ptr Thinned(const Cloud::Ptr& cloud, double voxel_m) {
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  const auto leaf = static_cast<float>(voxel_m);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.setInputCloud(cloud);
  Cloud::Ptr thinned(new Cloud);
  grid.filter(*thinned);
  return thinned;
}

// Fractions of a motion at constant twist (first order): At(f) = motion^f, f in [-1, 0] going back
// along it. The motion's angle and axis are taken apart once, not per point.
class MotionFraction {
 public:
  explicit MotionFraction(const Eigen::Isometry3d& motion)
      : rotation_(motion.linear()), translation_(motion.translation()) {}

  Eigen::Isometry3d At(double f) const {
    Eigen::Isometry3d part = Eigen::Isometry3d::Identity();
    part.linear() = Eigen::AngleAxisd(f * rotation_.angle(), rotation_.axis()).toRotationMatrix();
    part.translation() = f * translation_;
    return part;
  }

 private:
  Eigen::AngleAxisd rotation_;
  Eigen::Vector3d translation_;
};

}  // namespace

void ValidateLidarOdometryConfig(const LidarOdometryConfig& c) {
  using common::RequireValue;
  RequireValue(c.scan_voxel_m > 0.0, "scan_voxel", c.scan_voxel_m, "must be > 0");
  RequireValue(c.map_voxel_m > 0.0, "map_voxel", c.map_voxel_m, "must be > 0");
  RequireValue(c.max_range_m > c.min_range_m, "max_range", c.max_range_m, "must be > min_range");
  RequireValue(c.map_radius_m > 0.0, "map_radius", c.map_radius_m, "must be > 0");
  RequireValue(c.max_iterations >= 1, "max_iterations", c.max_iterations, "must be >= 1");
  RequireValue(c.max_correction_m > 0.0, "max_correction", c.max_correction_m, "must be > 0");
  RequireValue(c.max_correction_rad > 0.0, "max_correction_angle", c.max_correction_rad,
               "must be > 0");
  RequireValue(c.max_correspondence_m > 0.0, "max_correspondence", c.max_correspondence_m,
               "must be > 0");
}

struct LidarOdometry::Impl {
  Cloud::Ptr map_O{new Cloud};
  pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp;
};

LidarOdometry::LidarOdometry(const LidarOdometryConfig& config, const Eigen::Isometry3d& X_OL_start)
    : config_(config),
      impl_(std::make_unique<Impl>()),
      X_OL_(X_OL_start),
      motion_(Eigen::Isometry3d::Identity()),
      X_OL_last_map_(X_OL_start) {
  ValidateLidarOdometryConfig(config_);
  impl_->gicp.setMaximumIterations(config_.max_iterations);
  impl_->gicp.setMaxCorrespondenceDistance(config_.max_correspondence_m);
}

LidarOdometry::~LidarOdometry() = default;

int LidarOdometry::map_points() const { return static_cast<int>(impl_->map_O->size()); }

const Eigen::Isometry3d& LidarOdometry::AddScan(const Eigen::Matrix3Xf& points_L,
                                                const Eigen::VectorXf& time_offsets_s,
                                                double scan_period_s,
                                                const std::optional<Eigen::Matrix3d>& R_turn) {
  // the predicted motion over this scan interval
  Eigen::Isometry3d motion = motion_;
  if (R_turn) motion.linear() = *R_turn;
  // de-skewed into the sensor frame at the scan's end, cropped to the matching ranges
  const MotionFraction back_along(motion);
  Cloud::Ptr scan(new Cloud);
  scan->reserve(static_cast<std::size_t>(points_L.cols()));
  for (Eigen::Index i = 0; i < points_L.cols(); ++i) {
    const double range = static_cast<double>(points_L.col(i).norm());
    if (range < config_.min_range_m || range > config_.max_range_m) continue;
    const double f = static_cast<double>(time_offsets_s[i]) / scan_period_s - 1.0;
    const Eigen::Vector3f p_end = (back_along.At(f) * points_L.col(i).cast<double>()).cast<float>();
    scan->push_back(pcl::PointXYZ(p_end.x(), p_end.y(), p_end.z()));
  }
  const Cloud::Ptr thinned = Thinned(scan, config_.scan_voxel_m);

  const bool first = scans_++ == 0;
  if (!first) {
    // registered against the map from the prediction, when both have enough points for GICP's
    // covariances
    const Eigen::Isometry3d predicted = X_OL_ * motion;
    constexpr std::size_t kFewestPoints = 50;
    if (thinned->size() < kFewestPoints || impl_->map_O->size() < kFewestPoints) {
      last_accepted_ = false;
      ++rejected_scans_;
      motion_ = motion;
      X_OL_ = predicted;
      return X_OL_;
    }
    impl_->gicp.setInputSource(thinned);
    Cloud aligned;
    impl_->gicp.align(aligned, predicted.matrix().cast<float>());
    Eigen::Isometry3d registered = predicted;
    const Eigen::Matrix4d T = impl_->gicp.getFinalTransformation().cast<double>();
    registered.linear() =
        Eigen::Quaterniond(T.topLeftCorner<3, 3>()).normalized().toRotationMatrix();
    registered.translation() = T.topRightCorner<3, 1>();
    const Eigen::Isometry3d correction = predicted.inverse() * registered;
    last_accepted_ = impl_->gicp.hasConverged() && registered.matrix().allFinite() &&
                     correction.translation().norm() <= config_.max_correction_m &&
                     Eigen::AngleAxisd(correction.linear()).angle() <= config_.max_correction_rad;
    if (!last_accepted_) ++rejected_scans_;
    const Eigen::Isometry3d X_OL_new = last_accepted_ ? registered : predicted;
    motion_ = X_OL_.inverse() * X_OL_new;
    X_OL_ = X_OL_new;
  }

  // the map takes the scan when the sensor has moved or turned enough since the last one
  const Eigen::Isometry3d since = X_OL_last_map_.inverse() * X_OL_;
  if (first || since.translation().norm() >= config_.map_step_m ||
      Eigen::AngleAxisd(since.linear()).angle() >= config_.map_turn_rad) {
    X_OL_last_map_ = X_OL_;
    Cloud::Ptr grown(new Cloud);
    const Eigen::Vector3f p_OL = X_OL_.translation().cast<float>();
    const float radius2 = static_cast<float>(config_.map_radius_m * config_.map_radius_m);
    for (const pcl::PointXYZ& p : *impl_->map_O) {
      if ((p.getVector3fMap() - p_OL).squaredNorm() <= radius2) grown->push_back(p);
    }
    const Eigen::Isometry3f X_OL_f = X_OL_.cast<float>();
    for (const pcl::PointXYZ& p : *thinned) {
      const Eigen::Vector3f p_O = X_OL_f * p.getVector3fMap();
      grown->push_back(pcl::PointXYZ(p_O.x(), p_O.y(), p_O.z()));
    }
    impl_->map_O = Thinned(grown, config_.map_voxel_m);
    impl_->gicp.setInputTarget(impl_->map_O);
  }
  return X_OL_;
}

}  // namespace trav::mapping
