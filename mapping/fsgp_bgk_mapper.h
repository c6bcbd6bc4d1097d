#pragma once

#include <deque>
#include <vector>

#include <Eigen/Core>

#include "common/random.h"
#include "mapping/features.h"
#include "mapping/fsgp_config.h"
#include "mapping/sparse_gp.h"
#include "mapping/traversability_mapper.h"

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

  MapUpdateResult Update(const common::PointCloud& points_W, const Eigen::Isometry3d& X_WB,
                         double t_s) override;
  const common::GridLayers& map() const override { return map_; }

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
    Eigen::MatrixXd inputs;
    Eigen::Vector3d plane;
    Eigen::VectorXd heights;
  };
  // The prediction on the window's supported cells: inputs before standardisation (x, y, kappa,
  // g), elevation, variance and slope components.
  struct CellPrediction {
    std::vector<Eigen::Vector2i> cells;
    Eigen::MatrixXd raw_inputs;
    Eigen::VectorXd elevation;
    Eigen::VectorXd variance;
    Eigen::VectorXd df_dx;
    Eigen::VectorXd df_dy;
  };

  static GpInputs StandardisedInputs(const TrainingSet& training, bool pca);
  // FSGP-Accumulation: the last accumulate_frames windows within the window around p_WB.
  Eigen::Matrix3Xf AccumulateFrames(const Eigen::Matrix3Xf& window, const Eigen::Vector3d& p_WB);
  CellPrediction PredictCells(const TrainingSet& training, const GpInputs& inputs,
                              const Eigen::Vector2i& low, const Eigen::Vector2i& high) const;
  // The GP variance on every variance_stride-th cell, spread over the others of its block.
  Eigen::VectorXd StridedVariance(const Eigen::MatrixXd& test,
                                  const std::vector<Eigen::Vector2i>& cells,
                                  const Eigen::Vector2i& low, const Eigen::Vector2i& high) const;
  // The preliminary score of each predicted cell fused into the map (BGK, or replaced); returns
  // the mean uncertainty weight w_sigma over the cells fused (NaN: none, or no fusion).
  double Fuse(const CellPrediction& prediction, double t_s);
  void MarkObstacles(const Eigen::Matrix3Xf& below_robot, const Eigen::Vector2i& low,
                     const Eigen::Vector2i& high);
  void Smooth(const Eigen::Vector2i& low, const Eigen::Vector2i& high);
  // The smoothing kernel's radius in cells (0: no smoothing).
  int SmoothingRadiusCells() const;

  FsgpConfig config_;
  GpHyperparameters hyper_;
  common::Random random_;
  common::GridLayers map_;
  common::GridLayers fused_;              // BGK state M before smoothing, on the map's geometry
  std::deque<Eigen::Matrix3Xf> history_;  // FSGP-Accumulation
  SparseGp gp_;
};

/// The BGK update of one cell (the paper's equations): with w_t = exp(-lambda (t - t0)) and
/// w_sigma = 1 / (sigma^2 + eps) (or `fixed_gain` when > 0), M <- (w_t w_sigma M + M_pre) /
/// (w_t w_sigma + 1) and sigma^2 <- (w_t sigma^2 + sigma_pre^2) / (w_t + 1). An unknown cell (NaN)
/// takes the new values. Returns the w_sigma used (NaN for an unknown cell).
double BgkUpdate(double m_pre, double variance_pre, double t_s, double decay_rate, double epsilon,
                 double fixed_gain, float* m, float* variance, float* t0_s);

/// Normalised preliminary score: w_kappa N(kappa) + w_g N(g) + w_slope N(slope), N(a) = min(a /
/// max, 1).
double PreliminaryScore(const FsgpConfig& config, double curvature, double gradient_m,
                        double slope_rad);

}  // namespace trav::mapping
