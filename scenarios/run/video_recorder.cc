#include "scenarios/run/video_recorder.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "common/enum_names.h"
#include "common/stopwatch.h"
#include "mapping/traversability_mapper.h"
#include "renders/map_panel.h"
#include "renders/renderer.h"
#include "renders/video_writer.h"

namespace trav::scenarios {

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

namespace {

// LiDAR points drawn in a video frame: at most this many (each is one geom, drawn one by one by
// MuJoCo's renderer), and only within this distance of the sensor (where a chase camera sees them).
constexpr Eigen::Index kMaxDrawnPoints = 1200;
constexpr float kDrawnPointRange_m = 15.0f;
// Segments of the planned path drawn in a video frame, at most.
constexpr std::size_t kMaxPlanSegments = 60;

// The latest LiDAR frame's points (`points_W`: the frame placed in W) near the sensor, coloured by
// height (blue low, red high), evenly subsampled.
renders::ColoredPoints DrawablePoints(const lidar::LidarFrame& frame,
                                      const Eigen::Matrix3Xf& points_W) {
  std::vector<Eigen::Index> near;
  for (Eigen::Index i = 0; i < points_W.cols(); ++i) {
    if (frame.points_L.points.col(i).norm() < kDrawnPointRange_m) near.push_back(i);
  }
  const std::size_t stride =
      std::max<std::size_t>(1, (near.size() + kMaxDrawnPoints - 1) / kMaxDrawnPoints);
  const auto count = static_cast<Eigen::Index>((near.size() + stride - 1) / stride);
  renders::ColoredPoints drawable;
  drawable.size_px = 3.0f;
  drawable.points_W.resize(3, count);
  drawable.rgba.resize(4, count);
  for (Eigen::Index k = 0; k < count; ++k)
    drawable.points_W.col(k) = points_W.col(near[static_cast<std::size_t>(k) * stride]);
  if (count == 0) return drawable;
  const float low = drawable.points_W.row(2).minCoeff();
  const float range = std::max(0.5f, drawable.points_W.row(2).maxCoeff() - low);
  for (Eigen::Index k = 0; k < count; ++k) {
    const float t = (drawable.points_W(2, k) - low) / range;
    drawable.rgba.col(k) =
        Eigen::Vector4f(t, 0.3f + 0.4f * (1.0f - std::abs(2.0f * t - 1.0f)), 1.0f - t, 1.0f);
  }
  return drawable;
}

// The traversability layer as a coloured ground grid at the map's elevation.
renders::GroundGrid DrawableMap(const common::GridLayers& map) {
  renders::GroundGrid grid;
  grid.geometry = map.geometry();
  grid.values = map.Layer(mapping::layers::kTraversability);
  grid.heights_m = map.Layer(mapping::layers::kElevation);
  grid.alpha = 0.55f;
  return grid;
}

// Every `stride`-th point of a trajectory as a polyline `lift_m` above the terrain.
renders::Polyline GroundPolyline(const std::vector<common::TrajectoryPoint>& points,
                                 std::size_t stride, const sim::TerrainWorld& world, double lift_m,
                                 const Eigen::Vector4f& rgba) {
  renders::Polyline line;
  line.rgba = rgba;
  for (std::size_t i = 0; i < points.size(); i += stride) {
    const Eigen::Vector2d& p = points[i].position_W;
    line.points_W.emplace_back(p.x(), p.y(), world.GroundHeight(p) + lift_m);
  }
  return line;
}

// The top-down panel of the closed loop: the navigation map around the robot, the plan (white),
// the driven path (blue), the goal (magenta), the movers (orange), the robot (black) and the latest
// LiDAR points.
renders::PanelOverlay NavigationPanel(const ClosedLoop& loop,
                                      const std::vector<Eigen::Vector2d>& driven_W,
                                      const Eigen::Matrix3Xf& points_W) {
  const common::RobotState& state = loop.state();
  renders::PanelOverlay panel;
  renders::PanelPath planned;
  for (const common::TrajectoryPoint& p : loop.navigator()->trajectory().points()) {
    planned.points_W.push_back(p.position_W);
  }
  planned.rgb = Eigen::Vector3i(255, 255, 255);
  panel.paths.push_back(std::move(planned));
  panel.paths.push_back({driven_W, Eigen::Vector3i(30, 90, 255), 2});
  const Eigen::Index stride = std::max<Eigen::Index>(1, points_W.cols() / 3000);
  for (Eigen::Index i = 0; i < points_W.cols(); i += stride) {
    panel.points_W.push_back(points_W.col(i).head<2>().cast<double>());
  }
  panel.discs.push_back({loop.scenario().goal_W, 0.4, Eigen::Vector3i(230, 0, 230), true});
  for (const planner::MovingObstacle& mover : loop.predicted_movers()) {
    panel.discs.push_back(
        {mover.PositionAt(state.time_s), mover.radius_m, Eigen::Vector3i(255, 140, 0), true});
  }
  panel.discs.push_back({state.X_WB.translation().head<2>(), 0.3, Eigen::Vector3i(0, 0, 0), true});
  return panel;
}

// The map the panels show: the navigation map, or the truth's geometry before the first map.
const common::GridLayers& ShownMap(const ClosedLoop& loop) {
  return loop.navigation_map() != nullptr ? *loop.navigation_map() : *loop.truth();
}

}  // namespace

VideoRecorder::VideoRecorder(ClosedLoop* loop, const std::string& output_dir,
                             const DrivenPath* driven)
    : times_(&loop->times()), driven_(driven), frame_period_s_(1.0 / loop->scenario().video.fps) {
  const Scenario& scenario = loop->scenario();
  renderer_ =
      std::make_unique<renders::Renderer>(loop->mutable_simulation(), scenario.video.render);
  // the closed loop adds a square map panel to the right of the camera's view
  const bool navigate = scenario.mode == RunMode::kNavigate;
  const int panel_px = navigate ? scenario.video.render.height : 0;
  video_ = std::make_unique<renders::VideoWriter>(output_dir + "/video.mp4",
                                                  scenario.video.render.width + panel_px,
                                                  scenario.video.render.height, scenario.video.fps);
  camera_ = std::make_unique<VideoCamera>(scenario.video.camera, loop->world());
  if (navigate) {
    const common::GridGeometry& g = loop->truth()->geometry();
    no_map_ = Eigen::MatrixXf::Constant(g.num_x, g.num_y, NAN);
  }
  // tracking: the reference path on the ground
  if (loop->tracker() != nullptr) {
    const std::vector<common::TrajectoryPoint>& points = loop->tracker()->reference().points();
    overlay_.polylines.push_back(
        GroundPolyline(points, std::max<std::size_t>(1, points.size() / 400), loop->world(), 0.02,
                       Eigen::Vector4f(0.1f, 0.4f, 1.0f, 1.0f)));
  }
}

VideoRecorder::~VideoRecorder() = default;

void VideoRecorder::OnLidarFrame(const ClosedLoop& loop, const lidar::LidarFrame& frame,
                                 const Eigen::Matrix3Xf& points_W) {
  overlay_.points.assign(1, DrawablePoints(frame, points_W));
  if (loop.navigator() != nullptr) latest_points_W_ = points_W;
}

void VideoRecorder::OnMapUpdate(const ClosedLoop& loop) {
  // the closed loop shows the map in its panel: no need to draw it as thousands of geoms
  if (loop.navigator() == nullptr) overlay_.grids.assign(1, DrawableMap(*loop.map()));
}

void VideoRecorder::WriteNavigationFrame(const ClosedLoop& loop, const std::string& status) {
  const common::RobotState& now = loop.state();
  const Scenario& scenario = loop.scenario();
  const std::string text =
      fmt::format("t {:.1f} s   v {:.2f} m/s   goal {:.1f} m   {}", now.time_s, now.v_WB_B.x(),
                  (now.X_WB.translation().head<2>() - scenario.goal_W).norm(), status);
  overlay_.texts.assign(1, renders::TextLabel{text, renders::TextCorner::kTopLeft});
  renderer_->Render(loop.simulation(), camera_->View(now.X_WB, frame_period_s_), overlay_, &frame_);
  const common::GridLayers& shown = ShownMap(loop);
  const Eigen::MatrixXf& layer =
      loop.navigation_map() != nullptr ? shown.Layer(mapping::layers::kTraversability) : no_map_;
  const renders::Image panel = renders::DrawMapPanel(
      shown, layer, now.X_WB.translation().head<2>(), scenario.mapping.area.map_size_m,
      frame_.height, NavigationPanel(loop, driven_->points_W(), latest_points_W_));
  video_->Write(renders::SideBySide(frame_, panel));
}

void VideoRecorder::BeforePhysics(const ClosedLoop& loop) {
  if (loop.simulation().time() < next_frame_s_ - 1e-9) return;
  const common::Stopwatch render_start;
  if (loop.navigator() != nullptr) {
    WriteNavigationFrame(loop, loop.navigator()->statistics().last_status);
  } else {
    renderer_->Render(loop.simulation(), camera_->View(loop.state().X_WB, frame_period_s_),
                      overlay_, &frame_);
    video_->Write(frame_);
  }
  times_->Add("render", render_start.ElapsedMilliseconds());
  next_frame_s_ += frame_period_s_;
}

void VideoRecorder::OnStepChecked(const ClosedLoop& loop, const LoopStep& step) {
  if (loop.navigator() == nullptr || !TimeSeriesSampleDue(loop, step.index)) return;
  // the plan on the ground in the camera's view, as at most kMaxPlanSegments capsules: each is
  // one geom for the software renderer
  const std::vector<common::TrajectoryPoint>& points = loop.navigator()->trajectory().points();
  const std::size_t stride = std::max<std::size_t>(1, points.size() / kMaxPlanSegments + 1);
  overlay_.polylines.assign(1, GroundPolyline(points, stride, loop.world(), 0.05,
                                              Eigen::Vector4f(1.0f, 1.0f, 1.0f, 1.0f)));
}

void VideoRecorder::OnEnd(const ClosedLoop& loop, Outcome outcome) {
  if (loop.navigator() != nullptr) {
    WriteNavigationFrame(loop, std::string("outcome: ") + common::NameOf(outcome));
  }
  video_->Close();
  frames_written_ = video_->frames_written();
}

void MapPathsWriter::OnEnd(const ClosedLoop& loop, Outcome /*outcome*/) {
  const common::GridLayers& shown = ShownMap(loop);
  const sim::TerrainWorld& world = loop.world();
  const double span = std::max(world.geometry.Extent().x(), world.geometry.Extent().y());
  renders::WritePng(
      path_, renders::DrawMapPanel(shown, shown.Layer(mapping::layers::kTraversability),
                                   world.geometry.Center(), span, 800,
                                   NavigationPanel(loop, driven_->points_W(), Eigen::Matrix3Xf())));
}

}  // namespace trav::scenarios
