#pragma once

#include <Eigen/Core>

#include "mapping/fsgp_config.h"

namespace trav::mapping {

/// A sparse GP on M inducing points (the training set itself, as in FSGP): with inputs Z (M x D,
/// standardised) and heights z, the predictive mean is f* = m + K_*M (K_MM + s_n^2 I)^-1 (z - m)
/// and the variance s*^2 = k_** - K_*M (K_MM + s_n^2 I)^-1 K_M*, via a Cholesky factor (the noise
/// term is also the jitter). The mean m is the training heights' mean.
class SparseGp {
 public:
  /// Factorises the kernel matrix of `inputs` (one row per point) for `heights`.
  /// @returns false if the factorisation fails (then the model is unusable).
  bool Fit(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& heights,
           const GpHyperparameters& hyper);

  /// Mean at each row of `test_inputs` and the analytic gradient of the mean with respect to every
  /// input dimension (standardised units), one row per test point. O(T M D).
  void Predict(const Eigen::MatrixXd& test_inputs, Eigen::VectorXd* mean,
               Eigen::MatrixXd* mean_gradient) const;

  /// Predictive variance at each row of `test_inputs`. O(T M^2): the expensive part.
  void PredictVariance(const Eigen::MatrixXd& test_inputs, Eigen::VectorXd* variance) const;

  /// Log marginal likelihood of the training heights under `hyper` and its gradient with respect to
  /// theta = (log l_1..log l_D, log s_f^2, log s_n^2, log alpha (RQ only; 0 for SE)).
  /// Cost O(M^3). @returns -infinity if the kernel matrix is not positive definite.
  static double LogMarginalLikelihood(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& heights,
                                      const GpHyperparameters& hyper, Eigen::VectorXd* gradient);

  /// Raises the log marginal likelihood with up to `iterations` L-BFGS steps (liblbfgs) from
  /// `hyper`, which is updated in place when the likelihood improved. @returns the iterations made.
  static int OptimiseHyperparameters(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& heights,
                                     int iterations, GpHyperparameters* hyper);

  /// The prior variance s_f^2 of the fitted model (the variance far from any data).
  double prior_variance() const { return signal_variance_; }

  /// The kernel between two standardised inputs.
  static double Kernel(const GpHyperparameters& hyper, double signal_variance,
                       const Eigen::Ref<const Eigen::RowVectorXd>& a,
                       const Eigen::Ref<const Eigen::RowVectorXd>& b);

 private:
  GpHyperparameters hyper_{};
  double signal_variance_{1.0};
  double mean_{0.0};
  Eigen::MatrixXd inputs_;
  Eigen::MatrixXd cholesky_;        // lower factor L of K_MM + s_n^2 I
  Eigen::VectorXd alpha_;           // (K_MM + s_n^2 I)^-1 (z - m)
  mutable Eigen::MatrixXd kernel_;  // K_*M of the last prediction, reused between frames
};

}  // namespace trav::mapping
