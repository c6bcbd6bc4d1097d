#pragma once

#include "common/archive.h"
#include "common/grid.h"
#include "mapping/fsgp_config.h"

namespace trav::mapping {

/// Parameters of the ground-truth traversability (docs/ground-truth.md).
struct GroundTruthConfig {
  double neighbourhood_radius_m{
      0.3};  ///< metric neighbourhood of the slope, curvature and gradient terms [m]
  double clearance_m{0.115};  ///< the Scout Mini's ground clearance [m]
  /// An obstacle within the cell or within this radius of its centre makes it untraversable [m].
  /// 0: the cell itself; the planners add the robot's footprint (docs/navigation.md), so that the
  /// robot's size is counted once.
  double footprint_radius_m{0.0};
  /// The physical truth's limits (ComputePhysicalTruth), measured in MuJoCo at 1 m/s
  /// (docs/ground-truth.md): the steepest slope the robot climbs, and crosses without rolling over
  /// [deg]; the highest step it climbs (its rear wheels), the highest its front wheels get onto
  /// pushed by the rear ones, and the depth from which driving off tilts it 45 deg [m];
  /// `clearance_m` is its belly's height above the wheel contacts.
  double max_pitch_deg{40.0};
  double max_roll_deg{40.0};
  double max_step_m{0.16};
  double max_front_step_m{0.22};
  double max_drop_m{0.27};
  int headings{16};  ///< headings of the physical truth, evenly spaced over the full turn

  /// The keys of scenario section `ground_truth` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("neighbourhood_radius", &neighbourhood_radius_m, {0.01, 5.0});
    a->Field("clearance", &clearance_m, {0.01, 5.0});
    a->Field("footprint_radius", &footprint_radius_m, {0.0, 5.0});
    a->Field("max_pitch", &max_pitch_deg, {1.0, 89.0});
    a->Field("max_roll", &max_roll_deg, {1.0, 89.0});
    a->Field("max_step", &max_step_m, {0.001, 5.0});
    a->Field("max_front_step", &max_front_step_m, {0.001, 5.0});
    a->Field("max_drop", &max_drop_m, {0.001, 5.0});
    a->Field("headings", &headings, {2, 64});
  }
};

/// Ground-truth traversability on `map_geometry` from the dense noise-free world: `ground_m`
/// (ground height) and `obstacle_m` (height of obstacle surfaces above the ground, 0 where there is
/// none), both on `world_geometry`. Per map cell, over the world samples within the neighbourhood
/// radius (so the result does not depend on point density): slope of the least-squares plane,
/// curvature lambda_min / (sum lambda + 1e-6) of the samples' covariance and gradient mean |z_j -
/// z_centre|, on the surface (ground plus obstacles); combined with the mapper's weights and
/// normalisers (PreliminaryScore). A cell with an obstacle higher than the clearance within it or
/// within the footprint radius of its centre is untraversable (1). Layers: traversability, slope,
/// curvature, gradient, elevation.
common::GridLayers ComputeGroundTruth(const common::GridGeometry& map_geometry,
                                      const common::GridGeometry& world_geometry,
                                      const Eigen::MatrixXf& ground_m,
                                      const Eigen::MatrixXf& obstacle_m, const FsgpConfig& score,
                                      const GroundTruthConfig& config);

}  // namespace trav::mapping
