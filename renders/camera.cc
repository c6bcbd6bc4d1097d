#include "renders/camera.h"

#include <cmath>

#include "common/pose.h"

namespace trav::renders {

CameraView ChaseCamera::Update(const Eigen::Isometry3d& X_WB, double dt_s) {
  const Eigen::Vector3d forward = X_WB.linear().col(0);
  const double heading = std::atan2(forward.y(), forward.x());
  if (!initialised_ || params_.heading_time_constant_s <= 0.0) {
    heading_rad_ = heading;
    initialised_ = true;
  } else {
    const double alpha = 1.0 - std::exp(-dt_s / params_.heading_time_constant_s);
    heading_rad_ =
        common::WrapAngle(heading_rad_ + alpha * common::WrapAngle(heading - heading_rad_));
  }
  CameraView view;
  view.lookat_W = X_WB.translation() + Eigen::Vector3d(0, 0, params_.height_offset_m);
  view.distance_m = params_.distance_m;
  view.azimuth_deg = heading_rad_ * 180.0 / M_PI;
  view.elevation_deg = params_.elevation_deg;
  return view;
}

CameraView OverviewView(const Eigen::Vector3d& center_W, const Eigen::Vector2d& extent_m) {
  CameraView view;
  view.lookat_W = center_W;
  view.distance_m = 0.95 * extent_m.maxCoeff() + 5.0;
  view.azimuth_deg = 90.0;
  view.elevation_deg = -55.0;
  return view;
}

CameraView TopDownView(const Eigen::Vector3d& p_W, double height_m) {
  CameraView view;
  view.lookat_W = p_W;
  view.distance_m = height_m;
  view.azimuth_deg = 90.0;
  view.elevation_deg = -90.0;
  return view;
}

CameraView OrthographicTopDownView(const Eigen::Vector3d& p_W, double span_m) {
  constexpr double kFovyDeg = 2.0;
  CameraView view = TopDownView(p_W, 0.5 * span_m / std::tan(0.5 * kFovyDeg * M_PI / 180.0));
  view.fovy_deg = kFovyDeg;
  view.hide_canopy = true;
  return view;
}

CameraView OrbitView(const Eigen::Vector3d& p_W, double t_s, double period_s) {
  CameraView view;
  view.lookat_W = p_W + Eigen::Vector3d(0, 0, 0.3);
  view.distance_m = 6.0;
  view.azimuth_deg = 360.0 * t_s / period_s;
  view.elevation_deg = -25.0;
  return view;
}

}  // namespace trav::renders
