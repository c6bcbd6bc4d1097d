#include "mapping/sparse_gp.h"

#include <lbfgs.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>
#include <utility>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include <Eigen/Cholesky>

#include "common/check.h"

namespace trav::mapping {
namespace {

// Pairwise squared distances between the rows of a and b, scaled by the length scales.
Eigen::MatrixXd ScaledSquaredDistances(const Eigen::Ref<const Eigen::MatrixXd>& a,
                                       const Eigen::Ref<const Eigen::MatrixXd>& b,
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

// Flushes single-precision denormals to zero while alive (x86 MXCSR FTZ and DAZ), restoring the
// caller's mode after. The Cholesky factor of a compact-support kernel matrix fills in with
// entries that underflow float's normal range; computing on them as denormals made the
// factorisation 2.5 times slower. Values that small (< 1.2e-38) are zeros at this precision.
class FlushDenormalsToZero {
 public:
#if defined(__SSE2__)
  FlushDenormalsToZero() : saved_(_mm_getcsr()) {
    _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero);
  }
  ~FlushDenormalsToZero() { _mm_setcsr(saved_); }

 private:
  static constexpr unsigned kFlushToZero = 0x8000;
  static constexpr unsigned kDenormalsAreZero = 0x0040;
  unsigned saved_;
#endif
};

// The kernel at a squared scaled distance: squared exponential or rational quadratic.
double KernelOfSquaredDistance(const GpHyperparameters& hyper, double signal_variance,
                               double squared_distance) {
  if (hyper.kernel == KernelType::kSquaredExponential)
    return signal_variance * std::exp(-0.5 * squared_distance);
  return signal_variance *
         std::pow(1.0 + squared_distance / (2.0 * hyper.rq_alpha), -hyper.rq_alpha);
}

double HeightVariance(const Eigen::Ref<const Eigen::VectorXd>& heights) {
  const double mean = heights.mean();
  return std::max(1e-4, (heights.array() - mean).square().mean());
}

}  // namespace

double SparseGp::Kernel(const GpHyperparameters& hyper, double signal_variance,
                        const Eigen::Ref<const Eigen::RowVectorXd>& a,
                        const Eigen::Ref<const Eigen::RowVectorXd>& b) {
  const double d2 =
      (a - b).cwiseQuotient(hyper.length_scales.head(a.size()).transpose()).squaredNorm();
  return KernelOfSquaredDistance(hyper, signal_variance, d2);
}

double SparseGp::CutoffSquaredDistance() const {
  // exp(-25) = 1.4e-11: far below the noise jitter and the float factor's rounding
  return hyper_.kernel == KernelType::kSquaredExponential ? 50.0
                                                          : std::numeric_limits<double>::infinity();
}

double SparseGp::KernelOf(double squared_distance) const {
  return KernelOfSquaredDistance(hyper_, signal_variance_, squared_distance);
}

double SparseGp::RadialFactorOf(double squared_distance) const {
  if (hyper_.kernel == KernelType::kSquaredExponential) return KernelOf(squared_distance);
  return signal_variance_ *
         std::pow(1.0 + squared_distance / (2.0 * hyper_.rq_alpha), -hyper_.rq_alpha - 1.0);
}

template <typename Visit>
void SparseGp::ForNeighbours(const double* query, Visit visit) const {
  const double cutoff = CutoffSquaredDistance();
  const Eigen::Vector2i centre = buckets_.BucketOf(Eigen::Vector2d(query[0], query[1]));
  // a bucket is as wide as the cutoff: every neighbour lies in the 3 x 3 buckets around the query
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      buckets_.ForPointsIn(centre + Eigen::Vector2i(dx, dy), [&](int j) {
        const double* z = scaled_inputs_.view().col(j).data();
        double squared_distance = 0.0;
        for (Eigen::Index d = 0; d < dims_; ++d)
          squared_distance += (query[d] - z[d]) * (query[d] - z[d]);
        if (squared_distance < cutoff) visit(j, squared_distance);
      });
    }
  }
}

bool SparseGp::Fit(const Eigen::Ref<const Eigen::MatrixXd>& inputs,
                   const Eigen::Ref<const Eigen::VectorXd>& heights,
                   const GpHyperparameters& hyper) {
  TRAV_DEMAND(inputs.cols() >= 2 && inputs.cols() <= kMaxDims);
  TRAV_DEMAND(heights.size() == inputs.rows());
  hyper_ = hyper;
  dims_ = inputs.cols();
  const Eigen::Index m = inputs.rows();
  mean_ = heights.mean();
  signal_variance_ = hyper.signal_variance_ratio * HeightVariance(heights);
  inverse_length_scales_ = hyper_.length_scales.head(dims_).cwiseInverse();
  auto scaled_inputs = scaled_inputs_.Resize(dims_, m);
  scaled_inputs.noalias() = (inputs * inverse_length_scales_.asDiagonal()).transpose();

  // the bucket grid over the scaled (x, y): one bucket when every pair counts
  const double cutoff = CutoffSquaredDistance();
  const auto scaled_xy = scaled_inputs.topRows<2>();
  const double extent =
      (scaled_xy.rowwise().maxCoeff() - scaled_xy.rowwise().minCoeff()).maxCoeff();
  buckets_.Rebuild(scaled_xy, std::isfinite(cutoff) ? std::sqrt(cutoff) : std::max(1.0, extent));

  // an envelope factor in x order where it saves most of a dense factor's work: in double
  // precision and unblocked it does less per multiply-add (a factor of about 3 is an estimate);
  // without compact support every row's envelope is the whole triangle, and nothing is sorted
  envelope_ = false;
  if (std::isfinite(cutoff)) {
    OrderAlongX(cutoff);
    double envelope_work = 0.0;  // multiply-adds of the envelope factor, sum of squared widths
    for (Eigen::Index r = 0; r < m; ++r) {
      const double width = static_cast<double>(r - first_column_[static_cast<std::size_t>(r)]);
      envelope_work += width * width / 2.0;
    }
    envelope_ = 3.0 * envelope_work < std::pow(static_cast<double>(m), 3) / 6.0;
  }
  const bool factorised = envelope_ ? FactoriseEnvelope() : FactoriseDense();
  if (!factorised) return false;
  auto alpha = alpha_.Resize(m);
  auto centred = centred_.Resize(m);
  centred = heights.array() - mean_;
  if (envelope_) {
    SolveEnvelope(centred, alpha);
  } else {
    SolveDense(centred, alpha);
  }
  return alpha.allFinite();
}

void SparseGp::OrderAlongX(double cutoff) {
  const auto scaled_inputs = scaled_inputs_.view();
  const auto m = static_cast<int>(scaled_inputs.cols());
  order_.resize(static_cast<std::size_t>(m));
  std::iota(order_.begin(), order_.end(), 0);
  std::sort(order_.begin(), order_.end(), [&](int a, int b) {
    return std::make_tuple(scaled_inputs(0, a), scaled_inputs(1, a), a) <
           std::make_tuple(scaled_inputs(0, b), scaled_inputs(1, b), b);
  });
  rank_.resize(static_cast<std::size_t>(m));
  first_column_.resize(static_cast<std::size_t>(m));
  // a row's envelope starts at the first point closer along x than the cutoff: the squared x
  // difference, computed as ForNeighbours computes its first term, never exceeds a neighbour's
  // squared distance, so every neighbour lies within
  int first = 0;
  for (int r = 0; r < m; ++r) {
    rank_[static_cast<std::size_t>(order_[static_cast<std::size_t>(r)])] = r;
    const double x = scaled_inputs(0, order_[static_cast<std::size_t>(r)]);
    for (;; ++first) {
      const double dx = x - scaled_inputs(0, order_[static_cast<std::size_t>(first)]);
      if (dx * dx < cutoff) break;
    }
    first_column_[static_cast<std::size_t>(r)] = first;
  }
}

bool SparseGp::FactoriseEnvelope() {
  const auto scaled_inputs = scaled_inputs_.view();
  envelope_factor_.Reset(first_column_);
  for (int r = 0; r < static_cast<int>(order_.size()); ++r) {
    ForNeighbours(scaled_inputs.col(order_[static_cast<std::size_t>(r)]).data(),
                  [&](int j, double squared_distance) {
                    const int column = rank_[static_cast<std::size_t>(j)];
                    if (column <= r) envelope_factor_(r, column) = KernelOf(squared_distance);
                  });
    envelope_factor_(r, r) += hyper_.noise_std_m * hyper_.noise_std_m;
  }
  return envelope_factor_.Factorize();
}

void SparseGp::SolveEnvelope(const Eigen::Ref<const Eigen::VectorXd>& b,
                             Eigen::Ref<Eigen::VectorXd> x) {
  auto ordered = ordered_.Resize(b.size());
  for (Eigen::Index r = 0; r < b.size(); ++r) ordered[r] = b[order_[static_cast<std::size_t>(r)]];
  envelope_factor_.Solve(ordered);
  for (Eigen::Index r = 0; r < b.size(); ++r) x[order_[static_cast<std::size_t>(r)]] = ordered[r];
}

bool SparseGp::FactoriseDense() {
  const auto scaled_inputs = scaled_inputs_.view();
  const Eigen::Index m = scaled_inputs.cols();
  // K_MM + s_n^2 I, lower triangle (the upper is never read)
  auto kernel = kernel_.Resize(m, m);
  kernel.setZero();
  for (Eigen::Index i = 0; i < m; ++i) {
    ForNeighbours(scaled_inputs.col(i).data(), [&](int j, double squared_distance) {
      if (j >= i) kernel(j, i) = KernelOf(squared_distance);
    });
  }
  kernel.diagonal().array() += hyper_.noise_std_m * hyper_.noise_std_m;
  const FlushDenormalsToZero flush;
  auto factor_storage = factor_storage_.Resize(m, m);
  factor_storage = kernel.cast<float>();
  dense_factor_.emplace(factor_storage);
  return dense_factor_->info() == Eigen::Success;
}

void SparseGp::SolveDense(const Eigen::Ref<const Eigen::VectorXd>& b,
                          Eigen::Ref<Eigen::VectorXd> x) {
  // iterative refinement: x += K^-1 (b - K x), the solve in single precision and the residual in
  // double; each step gains about -log10(cond(K) * 6e-8) digits
  constexpr int kRefinementSteps = 3;
  const auto kernel = kernel_.view();
  x.setZero();
  auto residual = residual_.Resize(b.size());
  residual = b;
  auto correction = correction_.Resize(b.size());
  for (int step = 0; step <= kRefinementSteps; ++step) {
    correction = residual.cast<float>();
    dense_factor_->solveInPlace(correction);
    x += correction.cast<double>();
    residual = b;
    residual.noalias() -= kernel.selfadjointView<Eigen::Lower>() * x;
  }
}

void SparseGp::PredictVariance(const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
                               Eigen::Ref<Eigen::VectorXd> variance) const {
  const Eigen::Index t_count = test_inputs.rows();
  TRAV_DEMAND(variance.size() == t_count);
  if (envelope_) {
    VarianceEnvelope(test_inputs, variance);
  } else {
    VarianceDense(test_inputs, variance);
  }
}

void SparseGp::VarianceEnvelope(const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
                                Eigen::Ref<Eigen::VectorXd> variance) const {
  // k** - |L^-1 k_M*|^2, k_M* in the factor's order: its first nonzero is where the solve starts
  const auto m = static_cast<int>(scaled_inputs_.cols());
  auto cross_kernel = envelope_cross_kernel_.Resize(m);
  cross_kernel.setZero();
  DimsVector query(dims_);
  for (Eigen::Index t = 0; t < test_inputs.rows(); ++t) {
    query = test_inputs.row(t).transpose().cwiseProduct(inverse_length_scales_);
    int first = m;
    ForNeighbours(query.data(), [&](int j, double squared_distance) {
      const int r = rank_[static_cast<std::size_t>(j)];
      cross_kernel[r] = KernelOf(squared_distance);
      first = std::min(first, r);
    });
    if (first == m) {
      variance[t] = signal_variance_;
      continue;
    }
    variance[t] = std::max(
        0.0, signal_variance_ - envelope_factor_.SolveLowerSquaredNorm(cross_kernel, first));
    cross_kernel.tail(m - first).setZero();
  }
}

void SparseGp::VarianceDense(const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
                             Eigen::Ref<Eigen::VectorXd> variance) const {
  const Eigen::Index t_count = test_inputs.rows();
  auto cross_kernel = dense_cross_kernel_.Resize(scaled_inputs_.cols(), t_count);
  cross_kernel.setZero();
  DimsVector query(dims_);
  for (Eigen::Index t = 0; t < t_count; ++t) {
    query = test_inputs.row(t).transpose().cwiseProduct(inverse_length_scales_);
    ForNeighbours(query.data(), [&](int j, double squared_distance) {
      cross_kernel(j, t) = static_cast<float>(KernelOf(squared_distance));
    });
  }
  // k** - |L^-1 k_M*|^2, solved a block of columns at a time: the blocking buffers of Eigen's
  // triangular solve then stay within EIGEN_STACK_ALLOCATION_LIMIT whatever the number of columns
  const FlushDenormalsToZero flush;
  constexpr Eigen::Index kColumns = 32;
  for (Eigen::Index first = 0; first < t_count; first += kColumns) {
    dense_factor_->matrixL().solveInPlace(
        cross_kernel.middleCols(first, std::min(kColumns, t_count - first)));
  }
  for (Eigen::Index t = 0; t < t_count; ++t) {
    variance[t] =
        std::max(0.0, signal_variance_ - static_cast<double>(cross_kernel.col(t).squaredNorm()));
  }
}

template <typename KernelAndRadialFactor>
double SparseGp::SumOverNeighbours(const double* query, KernelAndRadialFactor kernel,
                                   double* gradient) const {
  const auto scaled_inputs = scaled_inputs_.view();
  const auto alpha = alpha_.view();
  double sum = 0.0;
  std::fill(gradient, gradient + dims_, 0.0);
  ForNeighbours(query, [&](int j, double squared_distance) {
    const double a = alpha[j];
    const auto [k, radial_factor] = kernel(j, squared_distance);
    sum += k * a;
    const double g = radial_factor * a;
    // scaled difference (u_d - z_jd) / l_d: one more 1 / l_d in the caller
    for (Eigen::Index d = 0; d < dims_; ++d) gradient[d] -= g * (query[d] - scaled_inputs(d, j));
  });
  return sum;
}

void SparseGp::Predict(const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
                       Eigen::Ref<Eigen::VectorXd> mean,
                       Eigen::Ref<Eigen::MatrixXd> mean_gradient) const {
  // f* = m + sum_j k_j alpha_j; d f* / d u_d = -(1 / l_d^2) sum_j G_j alpha_j (u_d - z_jd)
  const Eigen::Index t_count = test_inputs.rows();
  TRAV_DEMAND(mean.size() == t_count);
  TRAV_DEMAND(mean_gradient.rows() == t_count && mean_gradient.cols() == dims_);
  const bool squared_exponential = hyper_.kernel == KernelType::kSquaredExponential;  // G = k
  auto kernel = [&](int, double squared_distance) {
    const double k = KernelOf(squared_distance);
    return std::pair(k, squared_exponential ? k : RadialFactorOf(squared_distance));
  };
  DimsVector query(dims_), gradient(dims_);
  for (Eigen::Index t = 0; t < t_count; ++t) {
    query = test_inputs.row(t).transpose().cwiseProduct(inverse_length_scales_);
    mean[t] = mean_ + SumOverNeighbours(query.data(), kernel, gradient.data());
    mean_gradient.row(t) = gradient.cwiseProduct(inverse_length_scales_).transpose();
  }
}

void SparseGp::PredictOnLattice(const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
                                Eigen::Ref<Eigen::VectorXd> mean,
                                Eigen::Ref<Eigen::MatrixXd> mean_gradient) const {
  const Eigen::Index t_count = test_inputs.rows();
  TRAV_DEMAND(dims_ == 2 && hyper_.kernel == KernelType::kSquaredExponential);
  TRAV_DEMAND(mean.size() == t_count);
  TRAV_DEMAND(mean_gradient.rows() == t_count && mean_gradient.cols() == 2);
  const auto scaled_inputs = scaled_inputs_.view();
  const Eigen::Index m = scaled_inputs.cols();
  const double cutoff = CutoffSquaredDistance();
  for (int d = 0; d < 2; ++d) {
    std::vector<double>& values = lattice_coordinates_[d];
    values.resize(static_cast<std::size_t>(t_count));
    for (Eigen::Index t = 0; t < t_count; ++t)
      values[t] = test_inputs(t, d) * inverse_length_scales_[d];
    std::sort(values.begin(), values.end());
    values.erase(std::unique(values.begin(), values.end()), values.end());
    auto factors = lattice_factors_[d].Resize(m, static_cast<Eigen::Index>(values.size()));
    for (Eigen::Index i = 0; i < factors.cols(); ++i) {
      for (Eigen::Index j = 0; j < m; ++j) {
        // a neighbour lies within the cutoff along each axis: farther factors are never read
        const double difference = values[i] - scaled_inputs(d, j);
        factors(j, i) =
            difference * difference < cutoff ? std::exp(-0.5 * difference * difference) : 0.0;
      }
    }
  }
  auto factors_at = [&](int d, double value) {
    const std::vector<double>& values = lattice_coordinates_[d];
    const auto column = std::lower_bound(values.begin(), values.end(), value) - values.begin();
    return lattice_factors_[d].view().col(column).data();
  };
  DimsVector query(2), gradient(2);
  for (Eigen::Index t = 0; t < t_count; ++t) {
    query = test_inputs.row(t).transpose().cwiseProduct(inverse_length_scales_);
    const double* factor_x = factors_at(0, query[0]);
    const double* factor_y = factors_at(1, query[1]);
    auto kernel = [&](int j, double) {
      const double k = signal_variance_ * factor_x[j] * factor_y[j];
      return std::pair(k, k);
    };
    mean[t] = mean_ + SumOverNeighbours(query.data(), kernel, gradient.data());
    mean_gradient.row(t) = gradient.cwiseProduct(inverse_length_scales_).transpose();
  }
}

double SparseGp::LogMarginalLikelihood(const Eigen::Ref<const Eigen::MatrixXd>& inputs,
                                       const Eigen::Ref<const Eigen::VectorXd>& heights,
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
  const Eigen::Ref<const Eigen::MatrixXd>* inputs;
  const Eigen::Ref<const Eigen::VectorXd>* heights;
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

int SparseGp::OptimiseHyperparameters(const Eigen::Ref<const Eigen::MatrixXd>& inputs,
                                      const Eigen::Ref<const Eigen::VectorXd>& heights,
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
