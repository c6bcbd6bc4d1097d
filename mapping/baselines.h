#pragma once

#include <vector>

#include "common/random.h"
#include "mapping/features.h"
#include "mapping/fsgp_config.h"
#include "mapping/sparse_gp.h"
#include "mapping/strided_variance.h"
#include "mapping/traversability_mapper.h"
#include "mapping/window.h"

namespace trav::mapping {

/// Settings of the SGP baseline (Leininger et al., ICRA 2024; abeleinin/gp-navigation).
struct SgpConfig {
  MapArea area{};
  int inducing_points{500};    ///< M: every floor(N / M)-th point after sorting by x (scenario:
                               ///< mapping.max_training_points)
  double length_scale_m{0.7};  ///< SE kernel over (x, y) in metres
  double noise_std_m{0.03};
  double support_radius_m{0.8};
  int variance_stride{4};     ///< the variance layer exact on every n-th cell (StridedVariance;
                              ///< scenario: mapping.variance_stride, as FSGP-BGK's)
  int score_window_cells{5};  ///< step and flatness over 5 x 5 cells
  double weight_step{0.4}, weight_flatness{0.4}, weight_slope{0.2};
  double step_critical_m{0.3}, flatness_critical_rad{0.5236}, slope_critical_rad{0.5236};
};

/// The SGP baseline: a GP on (x, y) only with inducing points on a stride of the points sorted by
/// x, and the step (max - min height), flatness (angle of the plane fitted over 5 x 5 cells) and
/// slope
/// (|grad f|) score of Leininger et al.; each frame overwrites the cells it sees (no fusion).
class SgpMapper final : public TraversabilityMapper {
 public:
  explicit SgpMapper(const SgpConfig& config);
  MapUpdateResult Update(const common::PointCloud& points_W, const Eigen::Isometry3d& X_WB,
                         double t_s) override;
  const common::GridLayers& map() const override { return map_; }

 private:
  // The step (max - min), flatness (plane angle) and score of each predicted cell from the
  // elevations around it.
  void ScoreCells(const std::vector<Eigen::Vector2i>& cells);

  SgpConfig config_;
  common::GridLayers map_;
  SparseGp gp_;
  WindowCrop crop_;
  InverseDistanceWeighting support_;  // which cells have an inducing point near
  StridedVariance variance_;
  ObstacleMarker obstacles_;
};

/// Settings of the elevation-map baseline (Fankhauser et al., RA-L 2018;
/// ANYbotics/elevation_mapping).
struct ElevationMapConfig {
  MapArea area{};
  double range_noise_m{0.02};  ///< height noise of a point: range_noise + range_noise_growth d^2
  double range_noise_growth{0.001};    ///< [1/m]
  double mahalanobis_threshold{2.5};   ///< a point this many sigmas above the cell replaces it
  double neighbourhood_radius_m{0.3};  ///< slope, curvature and gradient terms over this radius
};

/// The EM baseline: a 2.5-D elevation map with per-cell Kalman fusion of point heights (a higher
/// point beyond the Mahalanobis threshold replaces the cell: a new obstacle), and the FSGP score's
/// slope, curvature and gradient terms (same weights) computed on the fused elevation.
class ElevationMapper final : public TraversabilityMapper {
 public:
  ElevationMapper(const ElevationMapConfig& config, const FsgpConfig& score);
  MapUpdateResult Update(const common::PointCloud& points_W, const Eigen::Isometry3d& X_WB,
                         double t_s) override;
  const common::GridLayers& map() const override { return map_; }

 private:
  ElevationMapConfig config_;
  FsgpConfig score_;
  common::GridLayers map_;
  WindowCrop crop_;
  ObstacleMarker obstacles_;
};

}  // namespace trav::mapping
