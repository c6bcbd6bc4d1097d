#include "mapping/envelope_cholesky.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace trav::mapping {
namespace {

using ConstSpan = Eigen::Map<const Eigen::VectorXd>;

// The dot product of two contiguous spans of `length` doubles.
double Dot(const double* a, const double* b, int length) {
  if (length <= 0) return 0.0;
  return ConstSpan(a, length).dot(ConstSpan(b, length));
}

}  // namespace

void EnvelopeCholesky::Reset(const std::vector<int>& first_column) {
  const std::size_t n = first_column.size();
  first_.assign(first_column.begin(), first_column.end());
  start_.resize(n + 1);
  start_[0] = 0;
  for (std::size_t i = 0; i < n; ++i) {
    TRAV_DEMAND(first_column[i] >= 0 && static_cast<std::size_t>(first_column[i]) <= i);
    start_[i + 1] = start_[i] + (i - static_cast<std::size_t>(first_column[i]) + 1);
  }
  // the full lower triangle's storage: later envelopes of up to n rows fit whatever their shape
  values_.reserve(n * (n + 1) / 2);
  values_.assign(start_[n], 0.0);
}

double& EnvelopeCholesky::operator()(int i, int j) {
  TRAV_DEMAND(i >= 0 && i < size() && j >= First(i) && j <= i);
  return Row(i)[j - First(i)];
}

bool EnvelopeCholesky::Factorize() {
  // row by row: L(i, j) = (A(i, j) - L(i, :j) . L(j, :j)) / L(j, j), both rows within their
  // envelopes, then L(i, i) = sqrt(A(i, i) - |L(i, :i)|^2)
  for (int i = 0; i < size(); ++i) {
    const int fi = First(i);
    double* row_i = Row(i);
    for (int j = fi; j < i; ++j) {
      const int fj = First(j);
      const int from = std::max(fi, fj);
      const double* row_j = Row(j);
      row_i[j - fi] =
          (row_i[j - fi] - Dot(row_i + (from - fi), row_j + (from - fj), j - from)) / row_j[j - fj];
    }
    const double pivot = row_i[i - fi] - Dot(row_i, row_i, i - fi);
    if (!(pivot > 0.0) || !std::isfinite(pivot)) return false;
    row_i[i - fi] = std::sqrt(pivot);
  }
  return true;
}

void EnvelopeCholesky::Solve(Eigen::Ref<Eigen::VectorXd> b) const {
  TRAV_DEMAND(b.size() == size());
  SolveLowerSquaredNorm(b, 0);
  // L^T x = y, by columns of L^T (rows of L): x_i = y_i / L(i, i), then y_k -= L(i, k) x_i
  for (int i = size() - 1; i >= 0; --i) {
    const int fi = First(i);
    const double* row_i = Row(i);
    b[i] /= row_i[i - fi];
    Eigen::Map<Eigen::VectorXd>(b.data() + fi, i - fi) -= b[i] * ConstSpan(row_i, i - fi);
  }
}

double EnvelopeCholesky::SolveLowerSquaredNorm(Eigen::Ref<Eigen::VectorXd> b,
                                               int first_nonzero) const {
  TRAV_DEMAND(b.size() == size() && first_nonzero >= 0);
  // L y = b: y_i = (b_i - L(i, :i) . y(:i)) / L(i, i), where y is zero before `first_nonzero`
  double squared_norm = 0.0;
  for (int i = first_nonzero; i < size(); ++i) {
    const int fi = First(i);
    const int from = std::max(fi, first_nonzero);
    const double* row_i = Row(i);
    b[i] = (b[i] - Dot(row_i + (from - fi), b.data() + from, i - from)) / row_i[i - fi];
    squared_norm += b[i] * b[i];
  }
  return squared_norm;
}

}  // namespace trav::mapping
