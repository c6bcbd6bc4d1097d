#pragma once

#include <array>

#include <Eigen/Geometry>

#include "common/enum_names.h"

namespace trav::renders {

/// A free camera looking at a point: MuJoCo's mjvCamera parameters, in W.
struct CameraView {
  Eigen::Vector3d lookat_W{Eigen::Vector3d::Zero()};  ///< [m]
  double distance_m{4.0};                             ///< from the camera to lookat [m]
  double azimuth_deg{0.0};    ///< direction the camera looks, about +z from +x [deg]
  double elevation_deg{-30};  ///< negative looks down [deg]
  /// Vertical field of view [deg], in (0, 160). A narrow one from far away is how a top-down view
  /// is made nearly orthographic: MuJoCo 2.2 has no orthographic projection.
  double fovy_deg{45.0};
  bool hide_canopy{false};  ///< do not draw tree crowns (geom group 2), so they hide nothing

  /// The keys of scenario key `video.camera_pose` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("lookat", &lookat_W, {-1e4, 1e4});
    a->Field("distance", &distance_m, {0.1, 1e4});
    a->Field("azimuth", &azimuth_deg, {-360.0, 360.0});
    a->Field("elevation", &elevation_deg, {-90.0, 90.0});
    a->Field("fovy", &fovy_deg, {1.0, 150.0});
    a->Field("hide_canopy", &hide_canopy);
  }
};

/// Which camera a video uses.
enum class CameraMode {
  kChase,     ///< behind and above the robot, following its heading smoothly
  kOverview,  ///< the whole world from high above at an angle, tree crowns hidden
  kTopDown,   ///< straight down onto the robot, nearly orthographic
  kOrbit,     ///< circling the robot
  kFixed,     ///< a pose given in the scenario
};

/// The names of CameraMode's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<CameraMode>, 5> kCameraModeNames{
    {{CameraMode::kChase, "chase"},
     {CameraMode::kOverview, "overview"},
     {CameraMode::kTopDown, "top_down"},
     {CameraMode::kOrbit, "orbit"},
     {CameraMode::kFixed, "fixed"}}};
constexpr const auto& EnumNames(CameraMode) { return kCameraModeNames; }

/// Parameters of the chase camera.
struct ChaseCameraParams {
  double distance_m{3.5};
  double elevation_deg{-22.0};
  double height_offset_m{0.3};          ///< lookat above the robot base [m]
  double heading_time_constant_s{0.6};  ///< smoothing of the heading [s], >= 0
};

/// A camera that follows the robot from behind; its heading lags the robot's with a first-order
/// filter so turns and bumps do not shake the video.
class ChaseCamera {
 public:
  explicit ChaseCamera(const ChaseCameraParams& params = {}) : params_(params) {}

  /// Moves the camera to follow X_WB after `dt_s` seconds and returns the view.
  CameraView Update(const Eigen::Isometry3d& X_WB, double dt_s);

 private:
  ChaseCameraParams params_;
  bool initialised_{false};
  double heading_rad_{0.0};
};

/// A view of a world of `extent_m` (x, y) centred on `center_W` from high above at an angle.
CameraView OverviewView(const Eigen::Vector3d& center_W, const Eigen::Vector2d& extent_m);

/// A view straight down onto `p_W` from `height_m` above it.
CameraView TopDownView(const Eigen::Vector3d& p_W, double height_m);

/// A nearly orthographic view straight down onto `p_W` showing `span_m` metres from the frame's
/// top to its bottom: a 2 deg field of view from far above (MuJoCo 2.2 has no orthographic
/// projection; heights of a few metres then shift points by under 2 %), tree crowns hidden.
CameraView OrthographicTopDownView(const Eigen::Vector3d& p_W, double span_m);

/// A view circling `p_W` once every `period_s` seconds (counter-clockwise from behind -x at t = 0),
/// 6 m away and 25 deg above the horizon.
CameraView OrbitView(const Eigen::Vector3d& p_W, double t_s, double period_s);

}  // namespace trav::renders
