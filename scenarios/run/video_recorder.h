#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "renders/image.h"
#include "renders/overlay.h"
#include "scenarios/run/closed_loop.h"
#include "scenarios/run/recorders.h"

namespace trav::renders {
class Renderer;
class VideoWriter;
}  // namespace trav::renders

namespace trav::scenarios {

class VideoCamera;

/// Records video.mp4 at the scenario's frame rate and camera (docs/video.md): the world with its
/// ground painted by terrain type, movers as walkers and carts, the latest LiDAR frames' points
/// (coloured by height, older frames fading), the map draped on the ground and, by mode, the
/// tracked reference, or in mode navigate the plan as a ribbon, the MPC's horizon, the goal, the
/// movers' predicted paths, a status line and the map panel beside the view (map, colour bar,
/// scale bar, legend; the driven path from `driven`), ending on a frame with the outcome and an
/// end card with the summary.
class VideoRecorder : public LoopObserver {
 public:
  /// Opens `<output_dir>/video.mp4`; its render time goes to `loop->times()` as "render".
  /// @throws std::runtime_error if GL or ffmpeg is missing.
  VideoRecorder(ClosedLoop* loop, const std::string& output_dir, const DrivenPath* driven);
  ~VideoRecorder() override;

  bool WantsPoints() const override { return true; }
  void OnLidarFrame(const ClosedLoop& loop, const lidar::LidarFrame& frame,
                    const Eigen::Matrix3Xf& points_W) override;
  void OnMapUpdate(const ClosedLoop& loop) override;
  void BeforePhysics(const ClosedLoop& loop) override;
  void OnStepChecked(const ClosedLoop& loop, const LoopStep& step) override;
  void OnEnd(const ClosedLoop& loop, Outcome outcome) override;

  int frames_written() const { return frames_written_; }

 private:
  // Fills overlay_ for a frame now; `status` is the planner's status (navigate).
  void ComposeOverlay(const ClosedLoop& loop, const std::string& status);
  // The movers as walkers (capsules) and carts (boxes longer than wide), their geoms hidden.
  void AddMovers(const ClosedLoop& loop);
  // The goal's marker and the perceived movers' predicted paths.
  void AddGoalAndPredictions(const ClosedLoop& loop);
  renders::Panel MapPanel(const ClosedLoop& loop, const std::string& info) const;
  void WriteFrame(const ClosedLoop& loop, const std::string& status);

  ModuleTimes* times_;
  const DrivenPath* driven_;
  const VideoSettings& settings_;
  std::unique_ptr<renders::Renderer> renderer_;
  std::unique_ptr<renders::VideoWriter> video_;
  std::unique_ptr<VideoCamera> camera_;
  renders::Overlay overlay_;  // its points and grids are set as frames and maps arrive
  renders::Image frame_;
  renders::Polyline reference_, plan_, horizon_;
  std::vector<double> walked_m_;  // distance each mover has walked [m]: its gait's phase
  Eigen::Matrix3Xf latest_points_W_;
  Eigen::MatrixXf no_map_;  // the panel's layer before the first map: all unknown
  double frame_period_s_;
  double next_frame_s_{0.0};
  double last_frame_s_{0.0};
  int frames_written_{0};
};

/// Writes map_paths.png at the end of a run in mode navigate: the navigation map of the whole
/// world with the plan, the driven path (from `driven`), the goal, the movers and the robot.
class MapPathsWriter : public LoopObserver {
 public:
  MapPathsWriter(const std::string& output_dir, const DrivenPath* driven)
      : path_(output_dir + "/map_paths.png"), driven_(driven) {}

  void OnEnd(const ClosedLoop& loop, Outcome outcome) override;

 private:
  std::string path_;
  const DrivenPath* driven_;
};

}  // namespace trav::scenarios
