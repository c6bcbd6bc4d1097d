#pragma once

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "common/scratch.h"
#include "mapping/bucket_grid.h"
#include "mapping/envelope_cholesky.h"
#include "mapping/fsgp_config.h"

namespace trav::mapping {

/// A sparse GP on M inducing points (the training set itself, as in FSGP): with inputs Z (M x D,
/// standardised) and heights z, the predictive mean is f* = m + K_*M (K_MM + s_n^2 I)^-1 (z - m)
/// and the variance s*^2 = k_** - K_*M (K_MM + s_n^2 I)^-1 K_M*, via a Cholesky factor (the noise
/// term is also the jitter). The mean m is the training heights' mean.
///
/// Three shortcuts make it fast on one core (mapping/README.md):
/// - Compact support. The squared-exponential kernel is below 1.4e-11 s^2 beyond 50 squared length
///   scales, and the first two inputs (x, y) alone bound the distance; kernel entries beyond that
///   are exact zeros, and a bucket grid over (x, y) visits only the pairs within it. With short
///   length scales on a 10 m window that is about one pair in eight. The rational-quadratic kernel
///   has heavy tails and visits every pair.
/// - An envelope factor. With the training points ordered along x, each row of K_MM reaches back
///   only to the first point within the cutoff along x, and its Cholesky factor keeps that
///   envelope (EnvelopeCholesky, double precision); a variance query's forward solve starts at its
///   first neighbour in that order. Fit takes it where its work is under a third of a dense
///   factor's (FSGP-BGK's 0.1 length scales: about a sixth), a dense factor otherwise (SGP's
///   0.7 m length scale, the rational-quadratic kernel).
/// - Mixed precision in the dense factor. K_MM is factorised in single precision (twice as fast)
///   and the weights (K_MM + s_n^2 I)^-1 (z - m) are refined to double precision by iterative
///   refinement against the double-precision K_MM, as LAPACK's dsposv does; the variance, which
///   only weighs the fusion, is taken from the single-precision factor.
///
/// Fitting and prediction reuse the model's storage (the kernel matrix is factorised in place):
/// once its sizes have been seen they allocate nothing. The L-BFGS steps do. The const queries
/// PredictOnLattice and the variance write that storage too: one thread at a time per model.
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

  /// Predict for a model of two inputs (x, y) and the squared-exponential kernel whose test points
  /// lie on a lattice (the cells of a grid: few distinct values along x and along y). The kernel
  /// factorises, exp(-(dx^2 + dy^2) / 2) = exp(-dx^2 / 2) exp(-dy^2 / 2), and each factor is taken
  /// once per distinct coordinate and training point instead of an `exp` per test and training
  /// point: O((X + Y) M) exponentials for X and Y distinct coordinates, then O(T M) products. The
  /// same neighbours summed in the same order as Predict; each kernel value within a few ulp of
  /// Predict's (a product of two rounded exponentials).
  void PredictOnLattice(const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
                        Eigen::Ref<Eigen::VectorXd> mean,
                        Eigen::Ref<Eigen::MatrixXd> mean_gradient) const;

  /// Predictive variance at each row of `test_inputs` (the caller sizes `variance` T): the
  /// expensive part, O(T M^2) with the dense factor (relative error about 1e-5 of s_f^2, single
  /// precision), O(T M w) with the envelope one (w its mean row width; double precision).
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

  /// True when the last Fit chose the envelope factor, false for the dense one.
  bool envelope_factor() const { return envelope_; }

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
  /// Sorts the training points along scaled x into order_ and rank_, and sets each row's envelope
  /// (first_column_): the first point in that order closer along x than `cutoff` allows.
  void OrderAlongX(double cutoff);
  /// Builds and factorises K_MM + s_n^2 I in the envelope / dense factor. @returns false if it
  /// is not positive definite.
  bool FactoriseEnvelope();
  bool FactoriseDense();
  /// x = (K_MM + s_n^2 I)^-1 b with the envelope factor / with the dense one, refined.
  void SolveEnvelope(const Eigen::Ref<const Eigen::VectorXd>& b, Eigen::Ref<Eigen::VectorXd> x);
  void SolveDense(const Eigen::Ref<const Eigen::VectorXd>& b, Eigen::Ref<Eigen::VectorXd> x);
  /// PredictVariance with the envelope factor / with the dense one.
  void VarianceEnvelope(const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
                        Eigen::Ref<Eigen::VectorXd> variance) const;
  void VarianceDense(const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
                     Eigen::Ref<Eigen::VectorXd> variance) const;
  /// Calls visit(j, squared scaled distance) for every training point j within the cutoff of the
  /// scaled input `query` (D values).
  template <typename Visit>
  void ForNeighbours(const double* query, Visit visit) const;
  /// The sum over the neighbours j of the scaled input `query` of k_j alpha_j, and in `gradient`
  /// (D values) -sum_j G_j alpha_j (u_d - z_jd) (still to be divided by l_d), with
  /// kernel(j, squared scaled distance) giving the pair (k_j, G_j): Predict's and
  /// PredictOnLattice's one loop, whichever way they take the kernel.
  template <typename KernelAndRadialFactor>
  double SumOverNeighbours(const double* query, KernelAndRadialFactor kernel,
                           double* gradient) const;

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
  // The two factors of K_MM + s_n^2 I (Fit chooses): the envelope one in the order along x, or
  // the dense one.
  bool envelope_{false};
  // the order along x (position -> training point), its inverse, and each row's envelope
  std::vector<int> order_, rank_, first_column_;
  EnvelopeCholesky envelope_factor_;
  common::ScratchMatrix<double, Eigen::Dynamic, 1> ordered_;  // a right-hand side in that order
  mutable common::ScratchMatrix<double, Eigen::Dynamic, 1> envelope_cross_kernel_;  // of a query
  common::ScratchMatrix<double> kernel_;  // the dense K_MM + s_n^2 I (lower triangle)
  // its single-precision Cholesky factor, computed in place in factor_storage_
  common::ScratchMatrix<float> factor_storage_;
  std::optional<Eigen::LLT<Eigen::Ref<Eigen::MatrixXf>>> dense_factor_;
  common::ScratchMatrix<double, Eigen::Dynamic, 1> residual_;
  common::ScratchMatrix<float, Eigen::Dynamic, 1> correction_;
  mutable common::ScratchMatrix<float> dense_cross_kernel_;   // K_M* of the last variance query
  common::ScratchMatrix<double, Eigen::Dynamic, 1> alpha_;    // (K_MM + s_n^2 I)^-1 (z - m)
  common::ScratchMatrix<double, Eigen::Dynamic, 1> centred_;  // z - m
  // PredictOnLattice's tables per axis: the distinct scaled test coordinates, sorted, and
  // exp(-(q - z_j)^2 / 2) for each training point j (row) and each of them (column)
  mutable std::array<std::vector<double>, 2> lattice_coordinates_;
  mutable std::array<common::ScratchMatrix<double>, 2> lattice_factors_;
};

}  // namespace trav::mapping
