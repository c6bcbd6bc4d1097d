#pragma once

#include <deque>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "common/point_cloud.h"

namespace trav::mapping {

/// Settings of the mover tracker.
struct MoverTrackerConfig {
  double range_m{15.0};      ///< points farther from the robot are ignored [m]
  double min_height_m{0.3};  ///< a point this high above its column's lowest is an object [m]
  double max_height_m{2.2};  ///< and no higher [m] (canopies, ceilings)
  /// A cluster reaching less high than this above its local ground is not an object [m]: patches
  /// of sloping or rough ground pass the point test but stay low; movers are 0.8 m or taller.
  double min_top_m{0.6};
  double column_m{1.0};      ///< column for the local ground [m]
  double cell_m{0.25};       ///< clustering grid [m]
  double max_radius_m{0.8};  ///< larger clusters are structures, not movers [m]
  /// Fewer points are no object [m]: stray returns; a pedestrian at 15 m still gives about 10 per
  /// frame.
  int min_points{5};
  double gate_m{1.0};         ///< a cluster farther than this from a track's prediction is new [m]
  double alpha{0.5};          ///< position gain of the alpha-beta filter, in (0, 1]
  double beta{0.3};           ///< velocity gain, in (0, 2)
  double drop_after_s{0.5};   ///< tracks unseen this long are dropped [s]
  int min_updates{3};         ///< updates before a track is reported
  double min_speed_m_s{0.2};  ///< slower tracks are static objects (in the map) [m/s]
  /// A track is moving when it is this far from where it was `displacement_window_s` ago [m]: the
  /// centroid of a trunk's visible side wanders with the view and the scan pattern fast enough to
  /// pass `min_speed_m_s`, but it stays put.
  double min_displacement_m{0.5};
  double displacement_window_s{1.0};  ///< [s], > 0
  /// A track is reported as a mover until this long after it last moved [s]: a pedestrian who
  /// pauses is still a pedestrian.
  double hold_s{2.0};
};

/// A tracked moving object.
struct TrackedMover {
  int id{0};
  Eigen::Vector2d position_W{Eigen::Vector2d::Zero()};  ///< centroid at t_s [m]
  Eigen::Vector2d velocity_W{Eigen::Vector2d::Zero()};  ///< [m/s]
  double radius_m{0.0};                                 ///< of the cluster's footprint [m]
  double t_s{0.0};                                      ///< time of the last update [s]
  int updates{0};
  /// Its recent positions (time, position), the last `displacement_window_s` and one before.
  std::deque<std::pair<double, Eigen::Vector2d>> recent_W;
  double last_moving_t_s{-std::numeric_limits<double>::infinity()};  ///< when it last moved [s]
};

/// Movers perceived from LiDAR frames alone: points standing above their local ground (the lowest
/// point of their column) and below a ceiling are clustered on a grid (8-connected cells); small
/// clusters are matched to tracks by nearest prediction within a gate and filtered at constant
/// velocity (alpha-beta filter). Static objects (trees, poles) become tracks too but are not
/// reported: a track is moving while it has been updated `min_updates` times, moves at
/// `min_speed_m_s` or more and is `min_displacement_m` from where it was `displacement_window_s`
/// ago, and is reported as a mover until `hold_s` after it last moved. Deterministic.
class MoverTracker {
 public:
  explicit MoverTracker(const MoverTrackerConfig& config = {});

  /// Updates the tracks with one frame (points in W, robot position, frame time).
  void Update(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB, double t_s);

  /// The tracks reported as movers.
  std::vector<TrackedMover> Movers() const;

  /// Every live track, static ones included.
  const std::vector<TrackedMover>& tracks() const { return tracks_; }

 private:
  MoverTrackerConfig config_;
  std::vector<TrackedMover> tracks_;
  int next_id_{1};
};

}  // namespace trav::mapping
