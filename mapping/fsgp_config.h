#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "common/enum_names.h"

namespace trav::mapping {

/// GP kernels over standardised inputs with one length scale per input (ARD).
enum class KernelType {
  kSquaredExponential,  ///< s^2 exp(-r^2 / 2)
  kRationalQuadratic,   ///< s^2 (1 + r^2 / (2 alpha))^-alpha
};

/// The names of KernelType's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<KernelType>, 2> kKernelTypeNames{
    {{KernelType::kSquaredExponential, "squared_exponential"},
     {KernelType::kRationalQuadratic, "rational_quadratic"}}};
constexpr const auto& EnumNames(KernelType) { return kKernelTypeNames; }

/// Hyperparameters of the sparse GP (inputs standardised per dimension: x, y, kappa, g).
struct GpHyperparameters {
  KernelType kernel{KernelType::kSquaredExponential};
  /// Length scales in standardised units for x, y, kappa, g (> 0). 0.1 of the window's standard
  /// deviation is about 0.3 m on a 10 m window: bumps and steps of the Scout Mini's size survive.
  /// kappa and g get long scales: they may shape the surface near features, but the height must be
  /// explained by position, or the slope (a derivative over x and y) would miss it.
  Eigen::Vector4d length_scales{0.1, 0.1, 3.0, 3.0};
  double signal_variance_ratio{1.0};  ///< s^2 as a multiple of the training heights' variance, > 0
  double noise_std_m{0.03};           ///< observation noise of a height [m], > 0 (also the jitter)
  double rq_alpha{1.0};               ///< rational-quadratic shape, > 0
};

/// Where every mapper looks and what it keeps: the local window, the rolling map's grid, the height
/// crop. Shared by FSGP-BGK and the baselines so that they map the same cells.
struct MapArea {
  double window_m{10.0};     ///< side of the square window around the robot [m]
  double resolution_m{0.2};  ///< map cell size [m]
  double map_size_m{30.0};   ///< side of the world-anchored rolling map [m], >= window
  /// Points higher than this above the base are ignored (tree crowns, ceilings) [m].
  double max_height_above_robot_m{1.0};
};

/// Everything FSGP-BGK does per frame (mapping/README.md gives the equations and the choices).
struct FsgpConfig {
  MapArea area{};  ///< window, grid and height crop
  /// Points higher than this above the lowest point of their 1 m column are not terrain [m] (> 0):
  /// the regression sees only the foot of walls and trunks, and cells whose points span more than
  /// this in height are marked untraversable (layer `obstacle`).
  double max_height_above_ground_m{0.3};
  // features
  double pre_voxel_m{0.1};            ///< voxel pre-downsampling [m]
  int neighbours{20};                 ///< k for curvature and gradient, >= 3
  double curvature_threshold{0.03};   ///< tau_kappa
  double gradient_threshold_m{0.03};  ///< tau_g [m]
  double feature_voxel_m{0.4};        ///< voxel for the non-feature points [m] (a 10 m window: 625)
  int max_training_points{500};       ///< M (inducing points), >= 10
  std::uint64_t seed{1};              ///< random subsampling
  bool pca{false};  ///< PCA decorrelation of the standardised inputs (fit on training)
  // GP
  GpHyperparameters gp{};
  int lbfgs_iterations{
      0};                 ///< L-BFGS steps maximising the marginal likelihood per frame (0: fixed)
  int idw_neighbours{5};  ///< K for kappa*, g* at the test cells
  double support_radius_m{0.8};  ///< a cell is observed if a training point lies this close [m]
  /// The predictive variance (O(T M^2), the costliest part) is computed on every n-th cell
  /// along x and y and taken by the others from that cell; it only weighs the fusion. >= 1
  int variance_stride{4};
  // preliminary score: weights sum to 1 (the released code's 0.3/0.3/0.2 rescaled)
  double weight_curvature{0.375};
  double weight_gradient{0.25};
  double weight_slope{0.375};
  double curvature_max{0.1};   ///< kappa* mapped to 1 at and above this
  double gradient_max_m{0.1};  ///< g* mapped to 1 at and above this [m]
  double slope_max_rad{
      0.5236};  ///< slope mapped to 1 at and above this (30 deg: the robot's limit)
  // fusion and smoothing
  bool fuse{true};                 ///< BGK fusion (false: FSGP, the latest frame's score)
  double decay_rate{1.0 / 600.0};  ///< lambda [1/s]
  double variance_epsilon{0.1};    ///< eps in w_sigma = 1 / (sigma^2 + eps)
  double smoothing_sigma_m{0.2};   ///< Gaussian smoothing [m] (0: none)
  double smoothing_radius_m{0.4};
  int accumulate_frames{1};  ///< FSGP-Accumulation: frames of clouds fed together (1: off)
};

/// Checks a config. @throws common::InputError naming the field ("mapping.<key>") and value.
void ValidateFsgpConfig(const FsgpConfig& config);

}  // namespace trav::mapping
