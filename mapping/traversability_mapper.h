#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/grid.h"
#include "common/point_cloud.h"

namespace trav::mapping {

/// Names of the layers every mapper outputs (1 = untraversable, 0 = easy; NaN = unknown).
namespace layers {
inline const std::string kElevation = "elevation";                   ///< [m]
inline const std::string kElevationVariance = "elevation_variance";  ///< [m^2]
inline const std::string kSlope = "slope";                           ///< [rad]
inline const std::string kCurvature = "curvature";                   ///< kappa, dimensionless
inline const std::string kGradient = "gradient";                     ///< g [m]
inline const std::string kTraversability = "traversability";         ///< cost in [0, 1]
inline const std::string kTraversabilityVariance = "traversability_variance";
inline const std::string kLastObserved = "last_observed";  ///< time of the last update [s]
/// 1 where the latest points of a cell showed a vertical face (FSGP-BGK), 0 where they did not.
inline const std::string kObstacle = "obstacle";
/// Time of the latest points that showed the cell's face [s] (NaN: never).
inline const std::string kObstacleSeen = "obstacle_seen";
/// Time of the first of the latest unbroken run of points that showed the cell's face [s]: a run
/// breaks where the cell is seen free or its face forgotten (NaN: never a face).
inline const std::string kObstacleSince = "obstacle_since";
/// Time of the first of the latest unbroken run of points that showed the cell free [s] (NaN: the
/// latest points showed a face, or none).
inline const std::string kFreeSince = "free_since";
/// common::Roughness of the highest points of the cell and its neighbours in the latest points
/// that showed them [m] (raw: no regression smooths a step away).
inline const std::string kRoughness = "roughness";
/// The lowest point any frame showed in the cell [m]: the ground there where it was ever seen (a
/// static world's ground does not rise; movers are kept out of the frames).
inline const std::string kFloor = "floor";
/// Where a face taller than the crop lies within its cell: the box of the points that showed it
/// (those more than 5 cm above the cell's lowest, not the ground at its foot) since its cell became
/// a face, as offsets from the cell's centre along x and y of W [m], each within half a cell; NaN
/// where the cell was seen free since, or its face showed no such points (a lower step, a drop):
/// the whole cell. The planners measure the
/// clearance to this box (planner::CellExtents): a 0.2 m cell holding a jamb's last 5 cm is no
/// 0.2 m of jamb.
inline const std::string kFaceXLow = "face_x_low";
inline const std::string kFaceXHigh = "face_x_high";  ///< (see kFaceXLow)
inline const std::string kFaceYLow = "face_y_low";    ///< (see kFaceXLow)
inline const std::string kFaceYHigh = "face_y_high";  ///< (see kFaceXLow)

/// Every layer above, in the order the mappers create them.
inline std::vector<std::string> All() {
  return {kElevation,
          kElevationVariance,
          kSlope,
          kCurvature,
          kGradient,
          kTraversability,
          kTraversabilityVariance,
          kLastObserved,
          kObstacle,
          kObstacleSeen,
          kObstacleSince,
          kFreeSince,
          kRoughness,
          kFloor,
          kFaceXLow,
          kFaceXHigh,
          kFaceYLow,
          kFaceYHigh};
}
}  // namespace layers

/// Outcome of one map update.
enum class MapUpdateStatus {
  kUpdated,       ///< the map took the frame
  kTooFewPoints,  ///< fewer than 10 valid points in the window: the map is unchanged
  kModelFailed,   ///< the model could not be fitted (ill-conditioned): the map is unchanged
};

/// Wall time of each stage of an update [ms].
struct StageTimes {
  double crop{0.0};
  double features{0.0};  ///< voxel, neighbours, features, sampling
  double fit{0.0};
  double predict{0.0};
  double fusion{0.0};
  double smoothing{0.0};
  double Total() const { return crop + features + fit + predict + fusion + smoothing; }
};

/// Result of one update.
struct MapUpdateResult {
  MapUpdateStatus status{MapUpdateStatus::kUpdated};
  int input_points{0};
  int dropped_invalid{0};  ///< NaN or infinite points
  int window_points{0};    ///< valid points in the window
  int training_points{0};
  int observed_cells{0};
  /// Mean BGK uncertainty weight w_sigma over the cells fused by this update (NaN: none, or a
  /// mapper without BGK fusion).
  double mean_fusion_weight{std::numeric_limits<double>::quiet_NaN()};
  StageTimes times{};
  /// The CPU and wall time [ms] of the work this update read from another mapper instead of doing
  /// it, as that mapper measured it on the same frame (FsgpBgkMapper::UnfusedOf: the regression;
  /// FsgpBgkMapper::OnFeaturesOf: the crop and the features); not in `times`. What the update would
  /// have cost alone is its own time plus these. 0 for a mapper doing all its own work.
  double shared_cpu_ms{0.0};
  double shared_wall_ms{0.0};
};

/// A traversability mapper: world-frame clouds, the robot pose and times in; a world-anchored
/// rolling grid out. Implementations: FSGP-BGK and its baselines.
class TraversabilityMapper {
 public:
  virtual ~TraversabilityMapper() = default;

  /// Takes one LiDAR frame (points in W) measured around `t_s` with the robot base at X_WB.
  virtual MapUpdateResult Update(const common::PointCloud& points_W, const Eigen::Isometry3d& X_WB,
                                 double t_s) = 0;

  /// The map (layers in mapping::layers).
  virtual const common::GridLayers& map() const = 0;

  /// Lets the mapper split each update's work with a helper thread of its own, for a mapper that
  /// runs beside other threads (the closed loop's mapping worker): the same maps bit for bit, in
  /// less wall time when a core is free. Mappers without independent parts ignore it.
  virtual void UseHelperThread() {}
};

}  // namespace trav::mapping
