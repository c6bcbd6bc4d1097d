#pragma once

#include <memory>
#include <string>

#include "scenarios/run/closed_loop.h"

namespace trav::scenarios {

/// The file name of a run's MCAP log in its folder.
inline constexpr char kMcapFileName[] = "run.mcap";

/// Writes `run.mcap`: the run as Foxglove opens it with no plug-in. Messages are JSON with
/// Foxglove's JSON schemas (third_party/foxglove_schemas), in zstd-compressed chunks, stamped
/// with simulation time (ns from the run's start). Frames follow REP-105: `world` (W, the truth),
/// `odom` (O, the frame of the pose estimate and the map; W itself with true poses), `base_link`
/// (the true base B) and `lidar` (the sensor L). Topics (docs/foxglove.md):
///
/// - `/tf` (foxglove.FrameTransforms): world -> base_link, world -> odom, base_link -> lidar, at
///   the rows of trajectory.csv (50 Hz);
/// - `/lidar/points` (foxglove.PointCloud): every LiDAR frame in `world`, each point placed with
///   its own sensor pose, with fields x, y, z, intensity (Livox reflectivity) and time (offset from
///   the frame's stamp [s]);
/// - `/map` (foxglove.Grid): the map in `odom`, each of its layers a float32 field (NaN: unknown),
///   at the first update and then at the first update `output.mcap_map_period` or more after the
///   last one written (0: every update);
/// - `/planner/path` and `/planner/trajectory` (foxglove.SceneUpdate): the A* waypoints and the
///   optimised trajectory of every plan; `/controller/horizon`: the MPC's predicted states of every
///   solve; `/movers/true` and `/movers/perceived`: discs with velocity arrows at 10 Hz; `/goal`;
/// - `/status` (foxglove.Log): the start, every plan with its reason and status, the outcome;
/// - `/timings` (trav.ModuleTimes): wall time of each module since the previous row [ms], the
///   rows of timeseries.csv (10 Hz).
class McapRecorder : public LoopObserver {
 public:
  /// Opens `<output_dir>/run.mcap` and registers the channels `loop` will fill (the planner's,
  /// the map's, the movers' only when it has them).
  McapRecorder(const ClosedLoop& loop, const std::string& output_dir);
  ~McapRecorder() override;
  McapRecorder(const McapRecorder&) = delete;
  McapRecorder& operator=(const McapRecorder&) = delete;

  bool WantsPoints() const override { return true; }
  void OnCommand(const ClosedLoop& loop) override;
  void OnLidarFrame(const ClosedLoop& loop, const lidar::LidarFrame& frame,
                    const Eigen::Matrix3Xf& points_W) override;
  void OnMapUpdate(const ClosedLoop& loop) override;
  void OnPhysicsStep(const ClosedLoop& loop, const LoopStep& step) override;
  void OnStepChecked(const ClosedLoop& loop, const LoopStep& step) override;
  /// Logs the outcome and closes the file. @throws common::InputError if it could not be written
  /// whole.
  void OnEnd(const ClosedLoop& loop, Outcome outcome) override;

 private:
  struct Log;
  std::unique_ptr<Log> log_;
};

}  // namespace trav::scenarios
