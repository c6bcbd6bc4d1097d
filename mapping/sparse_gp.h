#pragma once

#include <optional>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "common/scratch.h"
#include "mapping/bucket_grid.h"
#include "mapping/fsgp_config.h"

namespace trav::mapping {

/// A sparse GP on M inducing points (the training set itself, as in FSGP): with inputs Z (M x D,
/// standardised) and heights z, the predictive mean is f* = m + K_*M (K_MM + s_n^2 I)^-1 (z - m)
/// and the variance s*^2 = k_** - K_*M (K_MM + s_n^2 I)^-1 K_M*, via a Cholesky factor (the noise
/// term is also the jitter). The mean m is the training heights' mean.
///
/// Two shortcuts that change results only at the level of rounding make it fast on one core
/// (mapping/README.md):
/// - Compact support. The squared-exponential kernel is below 1.4e-11 s^2 beyond 50 squared length
///   scales, and the first two inputs (x, y) alone bound the distance; kernel entries beyond that
///   are exact zeros, and a bucket grid over (x, y) visits only the pairs within it. With short
///   length scales on a 10 m window that is about one pair in eight. The rational-quadratic kernel
///   has heavy tails and visits every pair.
/// - Mixed precision. K_MM is factorised in single precision (twice as fast) and the weights
///   (K_MM + s_n^2 I)^-1 (z - m) are refined to double precision by iterative refinement against
///   the double-precision K_MM, as LAPACK's dsposv does; the variance, which only weighs the
///   fusion, is taken from the single-precision factor.
///
/// Fitting and prediction reuse the model's storage (the kernel matrix is factorised in place):
/// once its sizes have been seen they allocate nothing. The L-BFGS steps do.
class SparseGp {
 public:
  /// The most input dimensions (x, y, kappa, g).
  static constexpr int kMaxDims = 4;

  /// Factorises the kernel matrix of `inputs` (one row per point, 2 to kMaxDims columns) for
  /// `heights`. @returns false if the factorisation fails (then the model is unusable).
  bool Fit(const Eigen::Ref<const Eigen::MatrixXd>& inputs,
           const Eigen::Ref<const Eigen::VectorXd>& heights, const GpHyperparameters& hyper);

  /// Mean at each row of `test_inputs` and the analytic gradient of the mean with respect to every
  /// input dimension (standardised units), one row per test point; the caller sizes the outputs
  /// T and T x D. O(T M D), M the training points within the kernel's cutoff.
  void Predict(const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
               Eigen::Ref<Eigen::VectorXd> mean, Eigen::Ref<Eigen::MatrixXd> mean_gradient) const;

  /// Predictive variance at each row of `test_inputs` (the caller sizes `variance` T), from the
  /// single-precision factor (relative error about 1e-5 of s_f^2). O(T M^2): the expensive part.
  void PredictVariance(const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
                       Eigen::Ref<Eigen::VectorXd> variance) const;

  /// Log marginal likelihood of the training heights under `hyper` and its gradient with respect to
  /// theta = (log l_1..log l_D, log s_f^2, log s_n^2, log alpha (RQ only; 0 for SE)).
  /// Cost O(M^3). @returns -infinity if the kernel matrix is not positive definite.
  static double LogMarginalLikelihood(const Eigen::Ref<const Eigen::MatrixXd>& inputs,
                                      const Eigen::Ref<const Eigen::VectorXd>& heights,
                                      const GpHyperparameters& hyper, Eigen::VectorXd* gradient);

  /// Raises the log marginal likelihood with up to `iterations` L-BFGS steps (liblbfgs) from
  /// `hyper`, which is updated in place when the likelihood improved. @returns the iterations made.
  static int OptimiseHyperparameters(const Eigen::Ref<const Eigen::MatrixXd>& inputs,
                                     const Eigen::Ref<const Eigen::VectorXd>& heights,
                                     int iterations, GpHyperparameters* hyper);

  /// The prior variance s_f^2 of the fitted model (the variance far from any data).
  double prior_variance() const { return signal_variance_; }

  /// The kernel between two standardised inputs.
  static double Kernel(const GpHyperparameters& hyper, double signal_variance,
                       const Eigen::Ref<const Eigen::RowVectorXd>& a,
                       const Eigen::Ref<const Eigen::RowVectorXd>& b);

 private:
  /// The squared scaled distance beyond which the kernel is taken as zero (infinite: never).
  double CutoffSquaredDistance() const;
  /// The kernel k and its radial factor G (dk/du_d = -G (u_d - z_d) / l_d^2) at a squared scaled
  /// distance.
  double KernelOf(double squared_distance) const;
  double RadialFactorOf(double squared_distance) const;
  /// Calls visit(j, squared scaled distance) for every training point j within the cutoff of the
  /// scaled input `query` (D values).
  template <typename Visit>
  void ForNeighbours(const double* query, Visit visit) const;

  // A vector of at most kMaxDims entries, on the stack.
  using DimsVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDims, 1>;

  GpHyperparameters hyper_{};
  double signal_variance_{1.0};
  double mean_{0.0};
  Eigen::Index dims_{0};
  DimsVector inverse_length_scales_;
  // D x M: training inputs over their length scales, one per column
  common::ScratchMatrix<double> scaled_inputs_;
  BucketGrid buckets_;  // the scaled training inputs' (x, y), buckets as wide as the cutoff
  common::ScratchMatrix<double> kernel_;  // K_MM + s_n^2 I (lower triangle)
  // its single-precision Cholesky factor, computed in place in factor_storage_
  common::ScratchMatrix<float> factor_storage_;
  std::optional<Eigen::LLT<Eigen::Ref<Eigen::MatrixXf>>> factor_;
  common::ScratchMatrix<double, Eigen::Dynamic, 1> alpha_;  // (K_MM + s_n^2 I)^-1 (z - m)
  common::ScratchMatrix<double, Eigen::Dynamic, 1> centred_, residual_;
  common::ScratchMatrix<float, Eigen::Dynamic, 1> correction_;
  mutable common::ScratchMatrix<float> cross_kernel_;  // K_M* of the last variance query
};

}  // namespace trav::mapping
