#include "mapping/fsgp_config.h"

#include <cmath>
#include <string>

#include "common/input_error.h"

namespace trav::mapping {
void ValidateFsgpConfig(const FsgpConfig& c) {
  const MapArea& a = c.area;
  common::RequireValue(a.window_m > 0.0, "window", a.window_m, "must be > 0");
  common::RequireValue(a.resolution_m > 0.0 && a.resolution_m <= a.window_m / 4, "resolution",
                       a.resolution_m, "must be > 0 and at most a quarter of the window");
  common::RequireValue(a.map_size_m >= a.window_m, "map_size", a.map_size_m,
                       "must be >= the window");
  // the grids a mapper holds: at most 4096 cells along the map and 1000 along the window
  common::RequireValue(a.map_size_m / a.resolution_m <= 4096.0, "map_size", a.map_size_m,
                       "gives more than 4096 cells along an axis at the resolution");
  common::RequireValue(a.window_m / a.resolution_m <= 1000.0, "window", a.window_m,
                       "gives more than 1000 cells along an axis at the resolution");
  common::RequireValue(a.max_height_above_ground_m > 0.0, "max_height_above_ground",
                       a.max_height_above_ground_m, "must be > 0");
  common::RequireValue(c.pre_voxel_m > 0.0, "pre_voxel", c.pre_voxel_m, "must be > 0");
  common::RequireValue(c.neighbours >= 3, "neighbours", c.neighbours, "must be >= 3");
  common::RequireValue(c.feature_voxel_m > 0.0, "feature_voxel", c.feature_voxel_m, "must be > 0");
  common::RequireValue(c.max_training_points >= 10, "max_training_points", c.max_training_points,
                       "must be >= 10");
  common::RequireValue((c.gp.length_scales.array() > 0.0).all(), "gp.length_scales",
                       c.gp.length_scales.minCoeff(), "must be > 0");
  common::RequireValue(c.gp.signal_variance_ratio > 0.0, "gp.signal_variance_ratio",
                       c.gp.signal_variance_ratio, "must be > 0");
  common::RequireValue(c.gp.noise_std_m > 0.0, "gp.noise_std", c.gp.noise_std_m, "must be > 0");
  common::RequireValue(c.gp.rq_alpha > 0.0, "gp.rq_alpha", c.gp.rq_alpha, "must be > 0");
  common::RequireValue(c.lbfgs_iterations >= 0, "lbfgs_iterations", c.lbfgs_iterations,
                       "must be >= 0");
  common::RequireValue(c.idw_neighbours >= 1, "idw_neighbours", c.idw_neighbours, "must be >= 1");
  common::RequireValue(c.variance_stride >= 1, "variance_stride", c.variance_stride,
                       "must be >= 1");
  common::RequireValue(c.support_radius_m > 0.0, "support_radius", c.support_radius_m,
                       "must be > 0");
  const double weights = c.weight_curvature + c.weight_gradient + c.weight_slope;
  common::RequireValue(c.weight_curvature >= 0.0 && c.weight_gradient >= 0.0 &&
                           c.weight_slope >= 0.0 && std::abs(weights - 1.0) < 1e-6,
                       "weights", weights, "must be >= 0 and sum to 1 (the paper's score)");
  common::RequireValue(c.curvature_max > 0.0, "curvature_max", c.curvature_max, "must be > 0");
  common::RequireValue(c.gradient_max_m > 0.0, "gradient_max", c.gradient_max_m, "must be > 0");
  common::RequireValue(c.slope_max_rad > 0.0, "slope_max", c.slope_max_rad, "must be > 0");
  common::RequireValue(c.decay_rate >= 0.0, "decay_rate", c.decay_rate, "must be >= 0");
  common::RequireValue(c.variance_epsilon > 0.0, "variance_epsilon", c.variance_epsilon,
                       "must be > 0");
  common::RequireValue(c.smoothing_sigma_m >= 0.0, "smoothing_sigma", c.smoothing_sigma_m,
                       "must be >= 0");
  common::RequireValue(c.smoothing_radius_m >= 0.0, "smoothing_radius", c.smoothing_radius_m,
                       "must be >= 0");
  common::RequireValue(c.accumulate_frames >= 1, "accumulate_frames", c.accumulate_frames,
                       "must be >= 1");
}

}  // namespace trav::mapping
