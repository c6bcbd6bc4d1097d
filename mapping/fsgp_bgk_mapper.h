#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/helper_thread.h"
#include "common/random.h"
#include "common/scratch.h"
#include "mapping/features.h"
#include "mapping/fsgp_config.h"
#include "mapping/sparse_gp.h"
#include "mapping/strided_variance.h"
#include "mapping/traversability_mapper.h"
#include "mapping/window.h"

namespace trav::mapping {

/// FSGP-BGK (Hou, Tan, Zhang, IROS 2025; mapping/README.md): per frame, feature-based sparse GP
/// regression of the terrain in a window around the robot, a preliminary traversability score from
/// curvature, gradient and the analytic slope of the GP mean, recursive precision- and
/// time-weighted (BGK) fusion per world cell, and normalised Gaussian smoothing. With `fuse =
/// false` it is the FSGP baseline; with `accumulate_frames > 1` and `fuse = false`,
/// FSGP-Accumulation.
class FsgpBgkMapper final : public TraversabilityMapper {
 public:
  /// @throws common::InputError for an invalid config.
  explicit FsgpBgkMapper(const FsgpConfig& config);

  /// The FSGP baseline on the regression of `source` (crop, training set, GP fit and prediction):
  /// `source`'s config without fusion, its every frame's regression read from `source`, which
  /// must have updated on the same frame (time and pose) just before. The same map, bit for bit,
  /// as FsgpBgkMapper(config without fusion) on its own: the regression reads no layer the fusion
  /// writes (the crop reads the floor that ObstacleMarker builds from the points alike in both).
  /// What lets `trav eval` score FSGP beside FSGP-BGK at the cost of one regression per frame; each
  /// update reports the regression's time, which it did not spend, as shared
  /// (MapUpdateResult::shared_cpu_ms). `source` must outlive it.
  static std::unique_ptr<FsgpBgkMapper> UnfusedOf(const FsgpBgkMapper& source);

  /// `source`'s method (its config) at another training-set size M, on `source`'s crop, voxel
  /// centroids and features of each frame (steps 1 to 3 up to the sampling to M): `source` must
  /// have updated on the same frame (time and pose) just before. The same map, bit for bit, as
  /// FsgpBgkMapper(that config) on its own: the features do not depend on M, and the crop reads the
  /// floor that ObstacleMarker builds from the points alike in both. What lets `trav eval`'s
  /// inducing-point ablation compute each frame's features once; each update reports the crop's
  /// and the features' time as shared. `source` must outlive it.
  static std::unique_ptr<FsgpBgkMapper> OnFeaturesOf(const FsgpBgkMapper& source,
                                                     int max_training_points);

  MapUpdateResult Update(const common::PointCloud& points_W, const Eigen::Isometry3d& X_WB,
                         double t_s) override;
  const common::GridLayers& map() const override { return map_; }
  /// The GP's mean on the helper while the updating thread computes its variance.
  void UseHelperThread() override;

  const FsgpConfig& config() const { return config_; }
  /// Hyperparameters in use (updated by the optional L-BFGS steps).
  const GpHyperparameters& hyperparameters() const { return hyper_; }

 private:
  // The GP's inputs (x, y, kappa, g) standardised by `mean` and `scale` and rotated by `rotation`
  // (PCA or identity), and the heights above the least-squares plane a x + b y + c.
  struct GpInputs {
    Eigen::RowVector4d mean;
    Eigen::RowVector4d scale;
    Eigen::Matrix4d rotation;
    common::ScratchMatrix<double> inputs;
    Eigen::Vector3d plane;
    common::ScratchMatrix<double, Eigen::Dynamic, 1> heights;
  };
  // The prediction on the window's supported cells: inputs before standardisation (x, y, kappa,
  // g), elevation, variance and slope components.
  struct CellPrediction {
    std::vector<Eigen::Vector2i> cells;
    common::ScratchMatrix<double> raw_inputs;
    common::ScratchMatrix<double, Eigen::Dynamic, 1> elevation, variance, df_dx, df_dy;
  };
  // Storage of the prediction's intermediate steps, kept between frames.
  struct PredictionScratch {
    common::ScratchMatrix<double, 2> centres_W;
    std::vector<Eigen::Vector2i> window_cells;
    std::vector<Eigen::Index> supported;
    common::ScratchMatrix<double> test, df_du;
  };

  // One frame's regression, kept until the next: what the fusion reads, and what a mapper made by
  // UnfusedOf takes instead of its own.
  struct Regression {
    MapUpdateResult result;  // status, counts, the stages' times and the time shared
    double cpu_ms{0.0};      // the CPU time this mapper spent on it
    // the crop and the features computed here (what OnFeaturesOf reads), and what they took,
    // CPU and wall
    bool featured{false};
    double features_cpu_ms{0.0}, features_wall_ms{0.0};
    double t_s{std::numeric_limits<double>::quiet_NaN()};
    Eigen::Vector3d p_WB{Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())};
    Eigen::Vector2i low{Eigen::Vector2i::Zero()}, high{Eigen::Vector2i::Zero()};  // window cells
  };

  // Steps 1 to 6 of Update into regression_, crop_ and prediction_ (on the map's geometry as
  // Update then recentres it), timed.
  void Regress(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB, double t_s);
  // The steps themselves: kUpdated, or the status of the step that ended them.
  MapUpdateStatus RegressionSteps(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB);
  // Steps 1 to 3 up to the sampling: the crop and the features into crop_ and extractor_, or
  // nothing (too few points). @returns whether there are features.
  bool CropAndFeatures(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB);
  // The crop of the frame: this mapper's, or its features source's.
  const WindowCrop& FrameCrop() const;
  // Throws std::logic_error unless `source` updated last on the frame at t_s and p_WB.
  static void ExpectSameFrame(const FsgpBgkMapper& source, double t_s, const Eigen::Vector3d& p_WB,
                              const char* made_by);
  // Fills inputs_ from the training set.
  void StandardiseInputs(const TrainingSet& training);
  // FSGP-Accumulation: the last accumulate_frames windows within the window around p_WB.
  Eigen::Map<const Eigen::Matrix3Xf, Eigen::Aligned16> AccumulateFrames(
      const Eigen::Ref<const Eigen::Matrix3Xf>& window, const Eigen::Vector3d& p_WB);
  // Fills prediction_ on the cells of `g` between low and high.
  void PredictCells(const common::GridGeometry& g, const TrainingSet& training,
                    const Eigen::Vector2i& low, const Eigen::Vector2i& high);
  // The preliminary score of each cell of `prediction` fused into the map (BGK, or replaced);
  // returns the mean uncertainty weight w_sigma over the cells fused (NaN: none, or no fusion).
  double Fuse(const CellPrediction& prediction, double t_s);
  void Smooth(const Eigen::Vector2i& low, const Eigen::Vector2i& high);
  // The smoothing kernel's radius in cells (0: no smoothing).
  int SmoothingRadiusCells() const;

  FsgpConfig config_;
  GpHyperparameters hyper_;
  common::Random random_;
  common::GridLayers map_;
  common::GridLayers fused_;  // BGK state M before smoothing, on the map's geometry
  SparseGp gp_;
  // Storage reused by every frame: after the first frames of a drive an update allocates nothing.
  WindowCrop crop_;
  std::vector<common::ScratchMatrix<float, 3>> history_;  // FSGP-Accumulation, a ring
  std::size_t history_next_{0};
  common::ScratchMatrix<float, 3> accumulated_;
  TrainingSetExtractor extractor_;
  GpInputs inputs_;
  InverseDistanceWeighting idw_;
  PredictionScratch scratch_;
  StridedVariance variance_;
  CellPrediction prediction_;
  ObstacleMarker obstacles_;
  std::unique_ptr<common::HelperThread> helper_;  // null: one thread
  Regression regression_;
  const FsgpBgkMapper* source_{nullptr};  // UnfusedOf: the mapper whose regression is fused
  // OnFeaturesOf: the mapper whose crop and features the regression samples
  const FsgpBgkMapper* features_source_{nullptr};
};

/// The BGK update of one cell (the paper's equations): with w_t = exp(-lambda (t - t0)) and
/// w_sigma = 1 / (sigma^2 + eps) (or `fixed_gain` when > 0), M <- (w_t w_sigma M + M_pre) /
/// (w_t w_sigma + 1) and sigma^2 <- (w_t sigma^2 + sigma_pre^2) / (w_t + 1). Given a
/// `reference_variance` the weight is relative to it: w_sigma = 2 / (eps ((sigma^2 + d) /
/// (reference + d) + 1)), between 0 and 2 / eps and 1 / eps at the reference, as the paper's weight
/// is for variances far below eps, whatever the GP's variance scale (d = 1e-12, so that two zero
/// variances weigh 1 / eps too). An unknown cell (NaN) takes the new values. Returns the w_sigma
/// used (NaN for an unknown cell).
double BgkUpdate(double m_pre, double variance_pre, double t_s, double decay_rate, double epsilon,
                 double fixed_gain, float* m, float* variance, float* t0_s,
                 std::optional<double> reference_variance = std::nullopt);

/// Normalised preliminary score: w_kappa N(kappa) + w_g N(g) + w_slope N(slope), N(a) = min(a /
/// max, 1).
double PreliminaryScore(const FsgpConfig& config, double curvature, double gradient_m,
                        double slope_rad);

}  // namespace trav::mapping
