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

// The video camera for the scenario's camera settings.
class VideoCamera {
 public:
  VideoCamera(const VideoSettings& settings, const sim::TerrainWorld& world) : settings_(settings) {
    const Eigen::Vector2d centre = world.geometry.Center();
    overview_ = renders::OverviewView(
        Eigen::Vector3d(centre.x(), centre.y(), world.height_m.mean()), world.geometry.Extent());
    overview_.hide_canopy = true;  // the robot stays visible under trees
  }

  // The view at time t_s with the robot at X_WB, `dt_s` after the previous frame.
  renders::CameraView View(const Eigen::Isometry3d& X_WB, double t_s, double dt_s) {
    switch (settings_.camera) {
      case renders::CameraMode::kChase:
        return chase_.Update(X_WB, dt_s);
      case renders::CameraMode::kOverview:
        return overview_;
      case renders::CameraMode::kTopDown:
        return renders::OrthographicTopDownView(X_WB.translation(), settings_.top_down_span_m);
      case renders::CameraMode::kOrbit:
        return renders::OrbitView(X_WB.translation(), t_s, settings_.orbit_period_s);
      case renders::CameraMode::kFixed:
        return settings_.camera_pose;
    }
    return overview_;
  }

 private:
  const VideoSettings& settings_;
  renders::ChaseCamera chase_;
  renders::CameraView overview_;
};

namespace {

// LiDAR points drawn in a video frame, at most (per frame shown), and only within this distance
// of the sensor (where a chase camera sees them).
constexpr Eigen::Index kMaxDrawnPoints = 20000;
constexpr float kDrawnPointRange_m = 30.0f;
// Segments of the planned path drawn in a video frame, at most.
constexpr std::size_t kMaxPlanSegments = 80;
// Stride of a walker's full gait cycle (two steps) per metre of its height.
constexpr double kStridePerHeight = 0.8;

// The colours of the navigation panel's symbols.
const Eigen::Vector3i kPlanRgb(255, 255, 255), kDrivenRgb(30, 90, 255), kPointsRgb(40, 120, 255);
const Eigen::Vector3i kGoalRgb(230, 0, 230), kMoverRgb(255, 140, 0), kRobotRgb(20, 20, 20);

// How the ground of `type` is painted.
renders::GroundMaterial GroundOf(sim::TerrainType type) {
  switch (type) {
    case sim::TerrainType::kRuin:
      return renders::GroundMaterial::kSoil;
    case sim::TerrainType::kStep:
    case sim::TerrainType::kStairs:
      return renders::GroundMaterial::kRock;
    case sim::TerrainType::kIndoor:
      return renders::GroundMaterial::kFloor;
    default:
      return renders::GroundMaterial::kGrass;
  }
}

// A LiDAR frame's points (`points_W`: the frame placed in W) near the sensor, coloured by height
// (blue low, red high, over `low_m` .. `low_m` + `range_m`), evenly subsampled.
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
  drawable.size_px = 2.5f;
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

// The traversability layer of `map` draped on the ground of `world`.
renders::GroundGrid DrawableMap(const common::GridLayers& map, const sim::TerrainWorld& world) {
  renders::GroundGrid grid;
  grid.geometry = map.geometry();
  grid.values = map.Layer(mapping::layers::kTraversability);
  grid.heights_m.resize(grid.values.rows(), grid.values.cols());
  for (int iy = 0; iy < grid.geometry.num_y; ++iy) {
    for (int ix = 0; ix < grid.geometry.num_x; ++ix) {
      grid.heights_m(ix, iy) =
          static_cast<float>(world.GroundHeight(grid.geometry.CellCenter(ix, iy)));
    }
  }
  grid.alpha = 0.4f;
  return grid;
}

// Points `lift_m` above the terrain along a path in W.
renders::Polyline GroundPolyline(const std::vector<Eigen::Vector2d>& points_W,
                                 const sim::TerrainWorld& world, double lift_m,
                                 const Eigen::Vector4f& rgba, double width_m) {
  renders::Polyline line;
  line.rgba = rgba;
  line.width_m = width_m;
  for (const Eigen::Vector2d& p : points_W) {
    line.points_W.emplace_back(p.x(), p.y(), world.GroundHeight(p) + lift_m);
  }
  return line;
}

// Every `stride`-th point of a trajectory's positions, and its last.
std::vector<Eigen::Vector2d> Positions(const std::vector<common::TrajectoryPoint>& points,
                                       std::size_t stride) {
  std::vector<Eigen::Vector2d> positions;
  for (std::size_t i = 0; i < points.size(); i += stride) positions.push_back(points[i].position_W);
  if (!points.empty() && (points.size() - 1) % stride != 0) {
    positions.push_back(points.back().position_W);
  }
  return positions;
}

// The top-down panel of the closed loop: the navigation map around the robot, the plan, the
// driven path, the goal, the movers, the robot's footprint and the latest LiDAR points.
renders::PanelOverlay NavigationPanel(const ClosedLoop& loop,
                                      const std::vector<Eigen::Vector2d>& driven_W,
                                      const Eigen::Matrix3Xf& points_W) {
  const common::RobotState& state = loop.state();
  renders::PanelOverlay panel;
  renders::PanelPath planned;
  for (const common::TrajectoryPoint& p : loop.navigator()->trajectory().points()) {
    planned.points_W.push_back(p.position_W);
  }
  planned.rgb = kPlanRgb;
  panel.paths.push_back(std::move(planned));
  panel.paths.push_back({driven_W, kDrivenRgb, 2});
  panel.points_rgb = kPointsRgb;
  const Eigen::Index stride = std::max<Eigen::Index>(1, points_W.cols() / 3000);
  for (Eigen::Index i = 0; i < points_W.cols(); i += stride) {
    panel.points_W.push_back(points_W.col(i).head<2>().cast<double>());
  }
  panel.discs.push_back({loop.scenario().goal_W, 0.4, kGoalRgb, true});
  for (const planner::MovingObstacle& mover : loop.predicted_movers()) {
    panel.discs.push_back({mover.PositionAt(state.time_s), mover.radius_m, kMoverRgb, true});
  }
  const common::Footprint footprint = loop.simulation().RobotFootprint();
  const Eigen::Vector3d forward = state.X_WB.linear().col(0);
  panel.boxes.push_back({state.X_WB.translation().head<2>(), std::atan2(forward.y(), forward.x()),
                         Eigen::Vector2d(footprint.half_length_m, footprint.half_width_m),
                         kRobotRgb});
  return panel;
}

// The legend of NavigationPanel's symbols.
std::vector<renders::LegendEntry> NavigationLegend() {
  using Symbol = renders::LegendEntry::Symbol;
  return {{Symbol::kLine, kPlanRgb, "plan"},           {Symbol::kLine, kDrivenRgb, "driven"},
          {Symbol::kDots, kPointsRgb, "LiDAR points"}, {Symbol::kDisc, kGoalRgb, "goal"},
          {Symbol::kDisc, kMoverRgb, "movers"},        {Symbol::kBox, kRobotRgb, "robot"}};
}

// The map the panels show: the navigation map, or the truth's geometry before the first map.
const common::GridLayers& ShownMap(const ClosedLoop& loop) {
  return loop.navigation_map() != nullptr ? *loop.navigation_map() : *loop.truth();
}

// Length of a path [m].
double PathLength(const std::vector<Eigen::Vector2d>& points_W) {
  double length = 0.0;
  for (std::size_t i = 1; i < points_W.size(); ++i)
    length += (points_W[i] - points_W[i - 1]).norm();
  return length;
}

}  // namespace

VideoRecorder::VideoRecorder(ClosedLoop* loop, const std::string& output_dir,
                             const DrivenPath* driven)
    : times_(&loop->times()),
      driven_(driven),
      settings_(loop->scenario().video),
      frame_period_s_(1.0 / loop->scenario().video.fps) {
  const Scenario& scenario = loop->scenario();
  renders::RenderConfig render = settings_.render;
  render.ground = GroundOf(loop->world().config.type);
  // the closed loop's map panel takes the right 3/8 of the frame
  if (scenario.mode == RunMode::kNavigate) {
    render.panel_width = static_cast<int>(std::lround(0.375 * render.width));
  }
  renderer_ = std::make_unique<renders::Renderer>(loop->mutable_simulation(), render);
  video_ = std::make_unique<renders::VideoWriter>(output_dir + "/video.mp4", render.width,
                                                  render.height, settings_.fps, settings_.crf);
  camera_ = std::make_unique<VideoCamera>(settings_, loop->world());
  if (scenario.mode == RunMode::kNavigate) {
    const common::GridGeometry& g = loop->truth()->geometry();
    no_map_ = Eigen::MatrixXf::Constant(g.num_x, g.num_y, NAN);
  }
  walked_m_.assign(static_cast<std::size_t>(loop->simulation().num_movers()), 0.0);
  // tracking: the reference path on the ground
  if (loop->tracker() != nullptr) {
    const std::vector<common::TrajectoryPoint>& points = loop->tracker()->reference().points();
    reference_ = GroundPolyline(Positions(points, std::max<std::size_t>(1, points.size() / 400)),
                                loop->world(), 0.02, Eigen::Vector4f(0.1f, 0.4f, 1.0f, 1.0f), 0.04);
  }
}

VideoRecorder::~VideoRecorder() = default;

void VideoRecorder::OnLidarFrame(const ClosedLoop& loop, const lidar::LidarFrame& frame,
                                 const Eigen::Matrix3Xf& points_W) {
  // the last video.lidar_frames frames: the latest opaque, older ones fading out
  std::vector<renders::ColoredPoints>& recent = overlay_.points;
  recent.push_back(DrawablePoints(frame, points_W));
  const auto kept = static_cast<std::size_t>(settings_.lidar_frames);
  if (recent.size() > kept) {
    recent.erase(recent.begin(), recent.end() - static_cast<std::ptrdiff_t>(kept));
  }
  for (std::size_t k = 0; k < recent.size(); ++k) {
    recent[k].rgba.row(3).setConstant(static_cast<float>(k + 1) / recent.size());
  }
  if (loop.navigator() != nullptr) latest_points_W_ = points_W;
}

void VideoRecorder::OnMapUpdate(const ClosedLoop& loop) {
  if (!settings_.map_overlay) return;
  const common::GridLayers* map = loop.navigator() != nullptr ? loop.navigation_map() : loop.map();
  if (map != nullptr) overlay_.grids.assign(1, DrawableMap(*map, loop.world()));
}

void VideoRecorder::OnStepChecked(const ClosedLoop& loop, const LoopStep& step) {
  if (loop.navigator() == nullptr || !TimeSeriesSampleDue(loop, step.index)) return;
  // the plan on the ground as a ribbon of at most kMaxPlanSegments capsules (each is one geom for
  // the software renderer), and the MPC's predicted horizon
  const std::vector<common::TrajectoryPoint>& points = loop.navigator()->trajectory().points();
  const std::size_t stride = std::max<std::size_t>(1, points.size() / kMaxPlanSegments + 1);
  plan_ = GroundPolyline(Positions(points, stride), loop.world(), 0.06,
                         Eigen::Vector4f(1.0f, 1.0f, 1.0f, 1.0f), 0.07);
  const Eigen::Matrix3Xd& horizon = loop.navigator()->tracker().predicted_states_W();
  std::vector<Eigen::Vector2d> horizon_W;
  for (Eigen::Index k = 0; k < horizon.cols(); ++k)
    horizon_W.emplace_back(horizon.col(k).head<2>());
  horizon_ =
      GroundPolyline(horizon_W, loop.world(), 0.1, Eigen::Vector4f(0.9f, 0.1f, 0.9f, 1.0f), 0.04);
}

void VideoRecorder::ComposeOverlay(const ClosedLoop& loop, const std::string& status) {
  renders::Overlay& overlay = overlay_;
  overlay.polylines.clear();
  if (!reference_.points_W.empty()) overlay.polylines.push_back(reference_);
  if (!plan_.points_W.empty()) overlay.polylines.push_back(plan_);
  if (!horizon_.points_W.empty()) overlay.polylines.push_back(horizon_);
  AddMovers(loop);
  overlay.texts.clear();
  if (loop.navigator() != nullptr) {
    const common::RobotState& now = loop.state();
    const Scenario& scenario = loop.scenario();
    overlay.texts.push_back(
        {fmt::format("t {:.1f} s   v {:.2f} m/s   goal {:.1f} m   {}", now.time_s, now.v_WB_B.x(),
                     (now.X_WB.translation().head<2>() - scenario.goal_W).norm(), status),
         renders::TextCorner::kTopLeft});
    overlay.panel = MapPanel(loop, fmt::format("t {:.1f} s   {}", now.time_s, status));
    AddGoalAndPredictions(loop);
  }
}

void VideoRecorder::AddGoalAndPredictions(const ClosedLoop& loop) {
  const sim::TerrainWorld& world = loop.world();
  const Eigen::Vector2d& goal = loop.scenario().goal_W;
  const Eigen::Vector4f magenta(0.9f, 0.0f, 0.9f, 1.0f), orange(1.0f, 0.55f, 0.0f, 1.0f);
  // the goal: a pole and a ring of the goal radius on the ground
  renders::Polyline pole;
  pole.rgba = magenta;
  pole.width_m = 0.08;
  pole.points_W = {Eigen::Vector3d(goal.x(), goal.y(), world.GroundHeight(goal)),
                   Eigen::Vector3d(goal.x(), goal.y(), world.GroundHeight(goal) + 1.5)};
  overlay_.polylines.push_back(pole);
  std::vector<Eigen::Vector2d> ring;
  const double radius_m = loop.scenario().navigation.goal_radius_m;
  for (int k = 0; k <= 24; ++k) {
    ring.push_back(goal +
                   radius_m * Eigen::Vector2d(std::cos(k * M_PI / 12), std::sin(k * M_PI / 12)));
  }
  overlay_.polylines.push_back(GroundPolyline(ring, world, 0.05, magenta, 0.05));
  // each perceived mover's predicted path over the next 2 s as an arrow
  const double t_s = loop.state().time_s;
  for (const planner::MovingObstacle& mover : loop.predicted_movers()) {
    if (mover.velocity_W.norm() < 0.05) continue;
    const Eigen::Vector2d from = mover.PositionAt(t_s), to = mover.PositionAt(t_s + 2.0);
    const Eigen::Vector2d back = 0.3 * (from - to).normalized();
    const Eigen::Vector2d side(-back.y(), back.x());
    overlay_.polylines.push_back(GroundPolyline({from, to}, world, 0.08, orange, 0.05));
    overlay_.polylines.push_back(GroundPolyline(
        {to + back + 0.6 * side, to, to + back - 0.6 * side}, world, 0.08, orange, 0.05));
  }
}

void VideoRecorder::AddMovers(const ClosedLoop& loop) {
  const sim::Simulation& simulation = loop.simulation();
  renders::Overlay& overlay = overlay_;
  overlay.walkers.clear();
  overlay.carts.clear();
  overlay.hidden_movers.clear();
  for (int i = 0; i < simulation.num_movers(); ++i) {
    const sim::MovingObstacle& mover = loop.movers()[static_cast<std::size_t>(i)];
    const Eigen::Isometry3d X_WO = simulation.MoverPose(i);
    if (mover.shape == sim::MoverShape::kCapsule) {
      renders::Walker walker;
      walker.X_WO = X_WO;
      walker.height_m = 2.0 * mover.half_height_m;
      walker.gait_phase_rad = 2.0 * M_PI * walked_m_[static_cast<std::size_t>(i)] /
                              (kStridePerHeight * walker.height_m);
      walker.rgba = mover.rgba;
      overlay.walkers.push_back(walker);
      overlay.hidden_movers.push_back(i);
    } else if (mover.shape == sim::MoverShape::kBox &&
               mover.box_half_extents_m.x() > mover.box_half_extents_m.y()) {
      // a box longer than wide goes lengthwise, as a cart does
      overlay.carts.push_back({X_WO,
                               Eigen::Vector3d(mover.box_half_extents_m.x(),
                                               mover.box_half_extents_m.y(), mover.half_height_m),
                               mover.rgba});
      overlay.hidden_movers.push_back(i);
    }
  }
}

renders::Panel VideoRecorder::MapPanel(const ClosedLoop& loop, const std::string& info) const {
  const renders::RenderConfig& render = renderer_->config();
  const common::GridLayers& shown = ShownMap(loop);
  const Eigen::MatrixXf& layer =
      loop.navigation_map() != nullptr ? shown.Layer(mapping::layers::kTraversability) : no_map_;
  const double span_m = loop.scenario().mapping.area.map_size_m;
  const renders::Image map = renders::DrawMapPanel(
      shown, layer, loop.state().X_WB.translation().head<2>(), span_m, render.panel_width,
      NavigationPanel(loop, driven_->points_W(), latest_points_W_));
  return renders::LayoutMapPanel(
      map, span_m, render.height, NavigationLegend(), info, renderer_->text_height_px(),
      [this](const std::string& text) { return renderer_->TextWidthPx(text); });
}

void VideoRecorder::WriteFrame(const ClosedLoop& loop, const std::string& status) {
  ComposeOverlay(loop, status);
  renderer_->Render(loop.simulation(),
                    camera_->View(loop.state().X_WB, loop.simulation().time(), frame_period_s_),
                    overlay_, &frame_);
  video_->Write(frame_);
}

void VideoRecorder::BeforePhysics(const ClosedLoop& loop) {
  const double t_s = loop.simulation().time();
  if (t_s < next_frame_s_ - 1e-9) return;
  const common::Stopwatch render_start;
  for (int i = 0; i < loop.simulation().num_movers(); ++i) {
    walked_m_[static_cast<std::size_t>(i)] +=
        loop.simulation().MoverVelocity(i).norm() * (t_s - last_frame_s_);
  }
  last_frame_s_ = t_s;
  WriteFrame(loop, loop.navigator() != nullptr ? loop.navigator()->statistics().last_status : "");
  times_->Add("render", render_start.ElapsedMilliseconds());
  next_frame_s_ += frame_period_s_;
}

void VideoRecorder::OnEnd(const ClosedLoop& loop, Outcome outcome) {
  if (loop.navigator() != nullptr) {
    const std::string result = std::string("outcome: ") + common::NameOf(outcome);
    WriteFrame(loop, result);
    // the end card: the outcome, the time and the path's length against the straight line
    const Scenario& scenario = loop.scenario();
    const double straight_m = (scenario.goal_W - scenario.start_W.position).norm();
    const double driven_m = PathLength(driven_->points_W());
    overlay_.texts.push_back(
        {fmt::format("{}\ntime {:.1f} s\npath {:.1f} m ({:.2f} x straight line)", result,
                     loop.state().time_s, driven_m, straight_m > 0.0 ? driven_m / straight_m : 0.0),
         renders::TextCorner::kCenter});
    const int card_frames = static_cast<int>(std::lround(settings_.end_card_s * settings_.fps));
    if (card_frames > 0) {
      renderer_->Render(loop.simulation(),
                        camera_->View(loop.state().X_WB, loop.simulation().time(), 0.0), overlay_,
                        &frame_);
      for (int k = 0; k < card_frames; ++k) video_->Write(frame_);
    }
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
