#pragma once

#include <array>
#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "common/archive.h"
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

/// What BGK's uncertainty weight w_sigma measures a cell's fused variance sigma^2 against
/// (BgkUpdate). The GP's variances are far below the paper's eps = 0.1, so the paper's weight
/// 1 / (sigma^2 + eps) is about 1 / eps on every cell; a relative weight 2 / (eps (sigma^2 /
/// reference + 1)) varies with the variance around 1 / eps whatever its scale.
enum class VarianceReference {
  kNone,        ///< the paper's weight 1 / (sigma^2 + eps)
  kFrameMean,   ///< relative to the frame's mean predicted variance
  kPrediction,  ///< relative to the new prediction's own variance: a cell's old value counts the
                ///< more, the less certain the new prediction is than it
};

/// The names of VarianceReference's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<VarianceReference>, 3> kVarianceReferenceNames{
    {{VarianceReference::kNone, "none"},
     {VarianceReference::kFrameMean, "frame_mean"},
     {VarianceReference::kPrediction, "prediction"}}};
constexpr const auto& EnumNames(VarianceReference) { return kVarianceReferenceNames; }

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

  /// The keys of scenario section `mapping.gp` (common/archive.h): the length scales as two pairs.
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Enum("kernel", &kernel);
    Eigen::Vector2d xy = length_scales.head<2>();
    Eigen::Vector2d features = length_scales.tail<2>();
    a->Field("length_scales_xy", &xy, {0.01, 100});
    a->Field("length_scales_features", &features, {0.0001, 10000.0});
    length_scales << xy, features;
    a->Field("signal_variance_ratio", &signal_variance_ratio, {1e-06, 1000.0});
    a->Field("noise_std", &noise_std_m, {1e-05, 10});
    a->Field("rq_alpha", &rq_alpha, {0.01, 100});
  }
};

/// Where every mapper looks and what it keeps: the local window, the rolling map's grid, the height
/// crops and the obstacle layer. Shared by FSGP-BGK and the baselines so that they map the same
/// cells from the same points (each option switchable for every method alike).
struct MapArea {
  double window_m{10.0};     ///< side of the square window around the robot [m]
  double resolution_m{0.2};  ///< map cell size [m]
  double map_size_m{30.0};   ///< side of the world-anchored rolling map [m], >= window
  /// Points higher than this above the base are ignored (tree crowns, ceilings) [m].
  double max_height_above_robot_m{1.0};
  /// Points higher than this above the local ground (WindowCrop) are not terrain [m] (> 0):
  /// the regression sees only the foot of walls and trunks, and cells whose points span more than
  /// this in height are marked untraversable (layer `obstacle`).
  double max_height_above_ground_m{0.3};
  /// A cell whose highest point stands more than this above the highest point of a side
  /// neighbour, or above the lowest point it ever showed (its floor), or whose floor stands more
  /// than this above a side neighbour's, is a step the robot cannot climb, marked untraversable
  /// with the faces [m] (0: no step test). The Scout Mini climbs 0.16 m at 1 m/s and not 0.17 m
  /// (docs/navigation.md).
  double max_step_m{0.15};
  /// A cell whose highest point stands more than this above the ground on both sides of it, one or
  /// two cells away along x, y or a diagonal, is a bump the robot would straddle with its chassis
  /// low over it: marked untraversable with the faces [m] (0: no bump test). The default suits
  /// the Scout Mini, whose chassis clears 0.115 m (sim::kDriveOverHeight_m), less 1.5 cm for the
  /// points' noise; a bump up to about 0.4 m wide passes between its wheels (wider ones, up to
  /// 0.6 m, are marked too).
  double max_bump_m{0.1};
  /// The deepest drop the robot drives down [m]: the Scout Mini tilts 45 deg down 0.27 m at 1 m/s
  /// (the physical truth's `max_drop`, docs/ground-truth.md).
  double max_drop_m{0.27};
  /// Cells never seen on a line between a cell seen in the frame and ground seen within this of
  /// it, more than `max_drop_m` lower and on average more steeply than `drop_slope_deg` below it,
  /// are a drop (ObstacleMarker::Drops): untraversable until seen [m] (0: no drop test).
  double drop_gap_m{3.0};
  double drop_slope_deg{20.0};  ///< [deg]
  /// Cells closer than this to the base lie in the sensor's ground blind zone [m]: the MID-360's
  /// lowest beam (7 deg down) meets flat ground about 2.4 m out from the Scout Mini's mount, and
  /// the body hides more. A short-lived face there that no point shows again is forgotten.
  double blind_radius_m{2.5};
  /// A face cell in the blind zone that points showed for less than this, and that no point has
  /// shown since for longer than this, is forgotten (its obstacle unknown again) [s]: the points of
  /// a walker the tracker missed would otherwise stay lethal where the ground is never seen free
  /// again. A face shown for longer is the world's (a wall the robot holds in its blind zone while
  /// it turns), and so is one beside such a face or beside a face shown after it (a wall's end,
  /// seen from close by only, continues the wall). 0: faces are never forgotten.
  double obstacle_memory_s{2.0};
  /// A face that points showed for `obstacle_memory_s` or longer (the world's) is cleared only by
  /// points that show the cell free for this long without a face between [s]: a wall's face
  /// that runs through a cell's middle leaves the cell's other half as ground, and a view along
  /// the wall shows that half alone (0, or `obstacle_memory_s` 0: the first free points clear any
  /// face).
  double obstacle_clear_s{0.5};
  /// The step test compares with each cell's floor too (StepAboveFloors in ObstacleMarker::Mark):
  /// heights seen seconds apart must agree to a few centimetres, which holds on the true pose; a
  /// run on an estimated pose (sim::PoseNoiseConfig::active) turns it off (MakeMapper), as the
  /// estimate's height drifts by more than the climbable step over a few metres.
  bool floor_steps{true};
  bool ground_crop{true};     ///< crop at max_height_above_ground_m (false: keep every height)
  bool obstacle_layer{true};  ///< mark the faces the crop removes as untraversable

  /// The ground crop's height: max_height_above_ground_m, or infinity without the crop [m].
  double GroundCropHeight() const {
    return ground_crop ? max_height_above_ground_m : std::numeric_limits<double>::infinity();
  }
};

/// Everything FSGP-BGK does per frame (mapping/README.md gives the equations and the choices).
struct FsgpConfig {
  MapArea area{};  ///< window, grid, height crops and obstacle layer
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
  double variance_epsilon{0.1};    ///< eps of the uncertainty weight w_sigma (VarianceReference)
  /// > 0: a fixed-gain filter, w_sigma = fixed_gain whatever the variance (the ablation of BGK's
  /// uncertainty weighting); 0: BGK.
  double fixed_gain{0.0};
  /// What the uncertainty weight measures a cell's variance against (docs/evaluation.md: the
  /// prediction's variance beats a fixed-gain filter of the same mean weight; the paper's plain
  /// weight is one).
  VarianceReference variance_reference{VarianceReference::kPrediction};
  double smoothing_sigma_m{0.2};  ///< Gaussian smoothing [m] (0: none)
  double smoothing_radius_m{0.4};
  int accumulate_frames{1};  ///< FSGP-Accumulation: frames of clouds fed together (1: off)

  /// The keys of scenario section `mapping` that configure the mapper (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("window", &area.window_m, {1, 100});
    a->Field("resolution", &area.resolution_m, {0.02, 2});
    a->Field("map_size", &area.map_size_m, {1, 1000});
    a->Field("max_height_above_robot", &area.max_height_above_robot_m, {0, 100});
    a->Field("max_height_above_ground", &area.max_height_above_ground_m, {0, 100});
    a->Field("max_step", &area.max_step_m, {0, 10});
    a->Field("max_bump", &area.max_bump_m, {0, 10});
    a->Field("max_drop", &area.max_drop_m, {0, 10});
    a->Field("drop_gap", &area.drop_gap_m, {0, 20});
    a->Field("drop_slope", &area.drop_slope_deg, {0, 89});
    a->Field("blind_radius", &area.blind_radius_m, {0, 100});
    a->Field("obstacle_memory", &area.obstacle_memory_s, {0, 100000});
    a->Field("obstacle_clear", &area.obstacle_clear_s, {0, 100000});
    a->Field("floor_steps", &area.floor_steps);
    a->Field("ground_crop", &area.ground_crop);
    a->Field("obstacle_layer", &area.obstacle_layer);
    a->Field("pre_voxel", &pre_voxel_m, {0, 1});
    a->Field("neighbours", &neighbours, {3, 200});
    a->Field("curvature_threshold", &curvature_threshold, {0, 10});
    a->Field("gradient_threshold", &gradient_threshold_m, {0, 10});
    a->Field("feature_voxel", &feature_voxel_m, {0, 2});
    a->Field("max_training_points", &max_training_points, {1, 3000});
    a->Field("seed", &seed);
    a->Field("pca", &pca);
    a->Map("gp", &gp);
    a->Field("lbfgs_iterations", &lbfgs_iterations, {0, 1000});
    a->Field("idw_neighbours", &idw_neighbours, {1, 100});
    a->Field("support_radius", &support_radius_m, {0.01, 20});
    a->Field("variance_stride", &variance_stride, {1, 100});
    a->Field("weight_curvature", &weight_curvature, {0, 100});
    a->Field("weight_gradient", &weight_gradient, {0, 100});
    a->Field("weight_slope", &weight_slope, {0, 100});
    a->Field("curvature_max", &curvature_max, {1e-06, 100});
    a->Field("gradient_max", &gradient_max_m, {1e-06, 100});
    a->Field("slope_max", &slope_max_rad, {0.001, 1.6});
    a->Field("fuse", &fuse);
    a->Field("decay_rate", &decay_rate, {0, 100});
    a->Field("variance_epsilon", &variance_epsilon, {1e-09, 10});
    a->Field("fixed_gain", &fixed_gain, {0, 1e6});
    a->Enum("variance_reference", &variance_reference);
    a->Field("smoothing_sigma", &smoothing_sigma_m, {0, 5});
    a->Field("smoothing_radius", &smoothing_radius_m, {0, 10});
    a->Field("accumulate_frames", &accumulate_frames, {1, 100});
  }
};

/// Checks a config. @throws common::InputError naming the key (relative: "window") and value.
void ValidateFsgpConfig(const FsgpConfig& config);

}  // namespace trav::mapping
