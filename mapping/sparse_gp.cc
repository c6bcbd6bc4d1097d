#include "mapping/sparse_gp.h"

#include <lbfgs.h>

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

namespace trav::mapping {
namespace {

// Pairwise squared distances between the rows of a and b, scaled by the length scales.
Eigen::MatrixXd ScaledSquaredDistances(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                                       const Eigen::VectorXd& length_scales) {
  const Eigen::MatrixXd as = a * length_scales.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd bs = b * length_scales.cwiseInverse().asDiagonal();
  Eigen::MatrixXd d2 = -2.0 * as * bs.transpose();
  d2.colwise() += as.rowwise().squaredNorm();
  d2.rowwise() += bs.rowwise().squaredNorm().transpose();
  return d2.cwiseMax(0.0);
}

// The kernel matrix from scaled squared distances, and G = dk/d(r^2) * (-2) (so that
// dk/du_d = -G (u_d - z_d) / l_d^2): SE G = k; RQ G = s^2 b^(-alpha - 1).
void KernelFromDistances(const GpHyperparameters& hyper, double signal_variance,
                         const Eigen::MatrixXd& d2, Eigen::MatrixXd* k, Eigen::MatrixXd* g) {
  if (hyper.kernel == KernelType::kSquaredExponential) {
    *k = signal_variance * (-0.5 * d2.array()).exp().matrix();
    if (g != nullptr) *g = *k;
    return;
  }
  const Eigen::ArrayXXd base = 1.0 + d2.array() / (2.0 * hyper.rq_alpha);
  *k = (signal_variance * base.pow(-hyper.rq_alpha)).matrix();
  if (g != nullptr) *g = (signal_variance * base.pow(-hyper.rq_alpha - 1.0)).matrix();
}

double HeightVariance(const Eigen::VectorXd& heights) {
  const double mean = heights.mean();
  return std::max(1e-4, (heights.array() - mean).square().mean());
}

}  // namespace

double SparseGp::Kernel(const GpHyperparameters& hyper, double signal_variance,
                        const Eigen::Ref<const Eigen::RowVectorXd>& a,
                        const Eigen::Ref<const Eigen::RowVectorXd>& b) {
  const double d2 =
      (a - b).cwiseQuotient(hyper.length_scales.head(a.size()).transpose()).squaredNorm();
  if (hyper.kernel == KernelType::kSquaredExponential) return signal_variance * std::exp(-0.5 * d2);
  return signal_variance * std::pow(1.0 + d2 / (2.0 * hyper.rq_alpha), -hyper.rq_alpha);
}

bool SparseGp::Fit(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& heights,
                   const GpHyperparameters& hyper) {
  hyper_ = hyper;
  inputs_ = inputs;
  mean_ = heights.mean();
  signal_variance_ = hyper.signal_variance_ratio * HeightVariance(heights);
  Eigen::MatrixXd k;
  KernelFromDistances(
      hyper_, signal_variance_,
      ScaledSquaredDistances(inputs, inputs, hyper_.length_scales.head(inputs.cols())), &k,
      nullptr);
  k.diagonal().array() += hyper_.noise_std_m * hyper_.noise_std_m;
  const Eigen::LLT<Eigen::MatrixXd> llt(k);
  if (llt.info() != Eigen::Success) return false;
  cholesky_ = llt.matrixL();
  alpha_ = llt.solve((heights.array() - mean_).matrix());
  return alpha_.allFinite();
}

void SparseGp::PredictVariance(const Eigen::MatrixXd& test_inputs,
                               Eigen::VectorXd* variance) const {
  Eigen::MatrixXd k_star;
  KernelFromDistances(
      hyper_, signal_variance_,
      ScaledSquaredDistances(test_inputs, inputs_, hyper_.length_scales.head(inputs_.cols())),
      &k_star, nullptr);
  // k** - |L^-1 k_M*|^2
  const Eigen::MatrixXd v = cholesky_.triangularView<Eigen::Lower>().solve(k_star.transpose());
  *variance =
      (signal_variance_ - v.colwise().squaredNorm().transpose().array()).cwiseMax(0.0).matrix();
}

void SparseGp::Predict(const Eigen::MatrixXd& test_inputs, Eigen::VectorXd* mean,
                       Eigen::MatrixXd* mean_gradient) const {
  const Eigen::Index dims = inputs_.cols();
  const Eigen::VectorXd length_scales = hyper_.length_scales.head(dims);
  // K_*M in a reused buffer (transformed in place: no temporaries of T x M)
  const Eigen::MatrixXd as = test_inputs * length_scales.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd bs = inputs_ * length_scales.cwiseInverse().asDiagonal();
  kernel_.noalias() = -2.0 * as * bs.transpose();
  kernel_.colwise() += as.rowwise().squaredNorm();
  kernel_.rowwise() += bs.rowwise().squaredNorm().transpose();
  kernel_ = kernel_.cwiseMax(0.0);
  // right-hand sides [alpha, alpha o z_1, ..., alpha o z_D]: d mean / d u_d =
  // -(1 / l_d^2) (u_d (G alpha) - G (alpha o z_d)), with G = K for the squared exponential
  Eigen::MatrixXd rhs(inputs_.rows(), dims + 1);
  rhs.col(0) = alpha_;
  for (Eigen::Index d = 0; d < dims; ++d) rhs.col(d + 1) = alpha_.cwiseProduct(inputs_.col(d));
  Eigen::MatrixXd products;
  if (hyper_.kernel == KernelType::kSquaredExponential) {
    // beyond r^2 = 50 (7 length scales) the kernel is below 1.4e-11 s^2: set to 0 without the
    // exponential, which with short length scales skips most pairs of a 10 m window
    for (Eigen::Index i = 0; i < kernel_.size(); ++i) {
      double& entry = kernel_.data()[i];
      entry = entry < 50.0 ? signal_variance_ * std::exp(-0.5 * entry) : 0.0;
    }
    products.noalias() = kernel_ * rhs;
    *mean = products.col(0).array() + mean_;
  } else {
    const Eigen::ArrayXXd base = 1.0 + kernel_.array() / (2.0 * hyper_.rq_alpha);
    *mean = (signal_variance_ * base.pow(-hyper_.rq_alpha)).matrix() * alpha_;
    mean->array() += mean_;
    kernel_ = signal_variance_ * base.pow(-hyper_.rq_alpha - 1.0);  // G
    products.noalias() = kernel_ * rhs;
  }
  mean_gradient->resize(test_inputs.rows(), dims);
  for (Eigen::Index d = 0; d < dims; ++d) {
    mean_gradient->col(d) =
        -(test_inputs.col(d).cwiseProduct(products.col(0)) - products.col(d + 1)) /
        (length_scales[d] * length_scales[d]);
  }
}

double SparseGp::LogMarginalLikelihood(const Eigen::MatrixXd& inputs,
                                       const Eigen::VectorXd& heights,
                                       const GpHyperparameters& hyper, Eigen::VectorXd* gradient) {
  const int dims = static_cast<int>(inputs.cols());
  const int n = static_cast<int>(inputs.rows());
  const Eigen::VectorXd length_scales = hyper.length_scales.head(dims);
  const double signal_variance = hyper.signal_variance_ratio * HeightVariance(heights);
  const double noise_variance = hyper.noise_std_m * hyper.noise_std_m;
  const Eigen::VectorXd y = heights.array() - heights.mean();

  const Eigen::MatrixXd d2 = ScaledSquaredDistances(inputs, inputs, length_scales);
  Eigen::MatrixXd k, g;
  KernelFromDistances(hyper, signal_variance, d2, &k, &g);
  Eigen::MatrixXd ky = k;
  ky.diagonal().array() += noise_variance;
  const Eigen::LLT<Eigen::MatrixXd> llt(ky);
  if (llt.info() != Eigen::Success) return -std::numeric_limits<double>::infinity();
  const Eigen::VectorXd alpha = llt.solve(y);
  const Eigen::MatrixXd l = llt.matrixL();
  const double log_likelihood =
      -0.5 * y.dot(alpha) - l.diagonal().array().log().sum() - 0.5 * n * std::log(2.0 * M_PI);
  if (gradient == nullptr) return log_likelihood;

  // dL/dtheta = 1/2 tr((alpha alpha^T - K^-1) dK/dtheta)
  const Eigen::MatrixXd w = alpha * alpha.transpose() - llt.solve(Eigen::MatrixXd::Identity(n, n));
  gradient->setZero(dims + 3);
  for (int d = 0; d < dims; ++d) {
    const Eigen::VectorXd u = inputs.col(d) / length_scales[d];
    Eigen::MatrixXd dd = u.replicate(1, n) - u.transpose().replicate(n, 1);
    dd = dd.cwiseProduct(dd);  // (du_d / l_d)^2
    (*gradient)[d] = 0.5 * (w.cwiseProduct(g.cwiseProduct(dd))).sum();
  }
  (*gradient)[dims] = 0.5 * (w.cwiseProduct(k)).sum();
  (*gradient)[dims + 1] = 0.5 * noise_variance * w.trace();
  if (hyper.kernel == KernelType::kRationalQuadratic) {
    const double a = hyper.rq_alpha;
    const Eigen::ArrayXXd base = 1.0 + d2.array() / (2.0 * a);
    const Eigen::MatrixXd dk =
        (a * k.array() * (-base.log() + d2.array() / (2.0 * a * base))).matrix();
    (*gradient)[dims + 2] = 0.5 * (w.cwiseProduct(dk)).sum();
  }
  return log_likelihood;
}

namespace {

// liblbfgs works on a C callback; the instance pointer carries the problem.
struct LbfgsProblem {
  const Eigen::MatrixXd* inputs;
  const Eigen::VectorXd* heights;
  GpHyperparameters hyper;
  int iterations{0};
};

int Progress(void* instance, const lbfgsfloatval_t*, const lbfgsfloatval_t*, const lbfgsfloatval_t,
             const lbfgsfloatval_t, const lbfgsfloatval_t, const lbfgsfloatval_t, int, int k, int) {
  static_cast<LbfgsProblem*>(instance)->iterations = k;
  return 0;
}

void FromTheta(const lbfgsfloatval_t* theta, int dims, GpHyperparameters* hyper) {
  for (int d = 0; d < dims; ++d) hyper->length_scales[d] = std::exp(theta[d]);
  hyper->signal_variance_ratio = std::exp(theta[dims]);
  hyper->noise_std_m = std::exp(0.5 * theta[dims + 1]);
  hyper->rq_alpha = std::exp(theta[dims + 2]);
}

lbfgsfloatval_t Evaluate(void* instance, const lbfgsfloatval_t* theta, lbfgsfloatval_t* gradient,
                         int n, lbfgsfloatval_t /*step*/) {
  auto* problem = static_cast<LbfgsProblem*>(instance);
  const int dims = n - 3;
  FromTheta(theta, dims, &problem->hyper);
  Eigen::VectorXd g;
  const double value =
      SparseGp::LogMarginalLikelihood(*problem->inputs, *problem->heights, problem->hyper, &g);
  if (!std::isfinite(value)) {
    for (int i = 0; i < n; ++i) gradient[i] = 0.0;
    return std::numeric_limits<double>::max();
  }
  // liblbfgs minimises: the negative log likelihood
  for (int i = 0; i < n; ++i) gradient[i] = -g[i];
  return -value;
}

}  // namespace

int SparseGp::OptimiseHyperparameters(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& heights,
                                      int iterations, GpHyperparameters* hyper) {
  if (iterations <= 0) return 0;
  const int dims = static_cast<int>(inputs.cols());
  const int n = dims + 3;
  lbfgsfloatval_t* theta = lbfgs_malloc(n);
  int made = 0;
  for (int d = 0; d < dims; ++d) theta[d] = std::log(hyper->length_scales[d]);
  theta[dims] = std::log(hyper->signal_variance_ratio);
  theta[dims + 1] = 2.0 * std::log(hyper->noise_std_m);
  theta[dims + 2] = std::log(hyper->rq_alpha);
  LbfgsProblem problem{&inputs, &heights, *hyper};
  lbfgs_parameter_t parameters;
  lbfgs_parameter_init(&parameters);
  parameters.max_iterations = iterations;
  parameters.linesearch = LBFGS_LINESEARCH_BACKTRACKING;
  lbfgsfloatval_t negative_likelihood = 0.0;
  lbfgs(n, theta, &negative_likelihood, Evaluate, Progress, &problem, &parameters);
  // keep the result only if it is a finite improvement
  GpHyperparameters candidate = *hyper;
  FromTheta(theta, dims, &candidate);
  const double before = LogMarginalLikelihood(inputs, heights, *hyper, nullptr);
  const double after = LogMarginalLikelihood(inputs, heights, candidate, nullptr);
  if (std::isfinite(after) && after > before) {
    *hyper = candidate;
    made = problem.iterations;
  }
  lbfgs_free(theta);
  return made;
}

}  // namespace trav::mapping
