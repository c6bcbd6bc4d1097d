#include "planner/minco.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace trav::planner {
namespace {

// Row vector of d^n/dt^n t^k for k = 0..5.
Eigen::Matrix<double, 1, 6> Basis(double t, int derivative) {
  Eigen::Matrix<double, 1, 6> basis = Eigen::Matrix<double, 1, 6>::Zero();
  for (int k = derivative; k < 6; ++k) {
    double factor = 1.0;
    for (int j = 0; j < derivative; ++j) factor *= k - j;
    double power = 1.0;
    for (int j = 0; j < k - derivative; ++j) power *= t;
    basis(k) = factor * power;
  }
  return basis;
}

}  // namespace

void MinimumJerkPolynomial::SetBoundary(const Eigen::MatrixXd& head, const Eigen::MatrixXd& tail,
                                        int num_pieces) {
  if (num_pieces < 1) {
    throw std::invalid_argument("MinimumJerkPolynomial: num_pieces must be >= 1, got " +
                                std::to_string(num_pieces));
  }
  if (head.rows() != 3 || tail.rows() != 3 || head.cols() != tail.cols() || head.cols() < 1) {
    throw std::invalid_argument("MinimumJerkPolynomial: head and tail must both be 3 x D");
  }
  num_pieces_ = num_pieces;
  head_ = head;
  tail_ = tail;
}

void MinimumJerkPolynomial::SetTail(const Eigen::MatrixXd& tail) {
  if (tail.rows() != 3 || tail.cols() != head_.cols()) {
    throw std::invalid_argument("MinimumJerkPolynomial: tail must be 3 x D");
  }
  tail_ = tail;
}

void MinimumJerkPolynomial::SetParameters(const Eigen::MatrixXd& inner_points,
                                          const Eigen::VectorXd& durations_s) {
  const int n = num_pieces_;
  if (n < 1 || inner_points.rows() != n - 1 || inner_points.cols() != head_.cols() ||
      durations_s.size() != n) {
    throw std::invalid_argument(
        "MinimumJerkPolynomial: expected (N - 1) x D inner points and N durations after "
        "SetBoundary");
  }
  if ((durations_s.array() <= 0.0).any() || !durations_s.allFinite()) {
    throw std::invalid_argument("MinimumJerkPolynomial: durations must be positive and finite");
  }
  durations_ = durations_s;
  band_.setZero(6 * n, 2 * kBandwidth + 1);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(6 * n, head_.cols());

  // head: position, velocity, acceleration of piece 0 at t = 0
  Band(0, 0) = 1.0;
  Band(1, 1) = 1.0;
  Band(2, 2) = 2.0;
  rhs.topRows(3) = head_;
  for (int i = 0; i < n - 1; ++i) {
    const double t1 = durations_(i), t2 = t1 * t1, t3 = t2 * t1, t4 = t3 * t1, t5 = t4 * t1;
    const int r = 6 * i;
    // jerk and snap continuity
    Band(r + 3, r + 3) = 6.0;
    Band(r + 3, r + 4) = 24.0 * t1;
    Band(r + 3, r + 5) = 60.0 * t2;
    Band(r + 3, r + 9) = -6.0;
    Band(r + 4, r + 4) = 24.0;
    Band(r + 4, r + 5) = 120.0 * t1;
    Band(r + 4, r + 10) = -24.0;
    // position at the end of piece i equals waypoint i
    const double position[6] = {1.0, t1, t2, t3, t4, t5};
    for (int k = 0; k < 6; ++k) Band(r + 5, r + k) = position[k];
    rhs.row(r + 5) = inner_points.row(i);
    // position, velocity and acceleration continuity
    for (int k = 0; k < 6; ++k) Band(r + 6, r + k) = position[k];
    Band(r + 6, r + 6) = -1.0;
    const double velocity[5] = {1.0, 2.0 * t1, 3.0 * t2, 4.0 * t3, 5.0 * t4};
    for (int k = 0; k < 5; ++k) Band(r + 7, r + 1 + k) = velocity[k];
    Band(r + 7, r + 7) = -1.0;
    const double acceleration[4] = {2.0, 6.0 * t1, 12.0 * t2, 20.0 * t3};
    for (int k = 0; k < 4; ++k) Band(r + 8, r + 2 + k) = acceleration[k];
    Band(r + 8, r + 8) = -2.0;
  }
  // tail: position, velocity, acceleration of the last piece at its end
  const int r = 6 * (n - 1);
  for (int d = 0; d < 3; ++d) {
    const Eigen::Matrix<double, 1, 6> basis = Basis(durations_(n - 1), d);
    for (int k = d; k < 6; ++k) Band(r + 3 + d, r + k) = basis(k);
  }
  rhs.bottomRows(3) = tail_;
  FactorizeAndSolve(&rhs);
  coefficients_ = std::move(rhs);
}

// Band Gaussian elimination without pivoting (Golub and Van Loan, Matrix Computations, algorithm
// 4.3.1). Eigen has no banded solver, and a general sparse LU would redo its analysis on a matrix
// whose pattern never changes; MINCO's row order keeps every pivot nonzero for positive durations.
void MinimumJerkPolynomial::FactorizeAndSolve(Eigen::MatrixXd* rhs) {
  const int size = 6 * num_pieces_;
  for (int k = 0; k < size; ++k) {
    const int last = std::min(k + kBandwidth, size - 1);
    const double pivot = Band(k, k);
    for (int i = k + 1; i <= last; ++i) Band(i, k) /= pivot;
    for (int j = k + 1; j <= last; ++j) {
      const double upper = Band(k, j);
      if (upper == 0.0) continue;
      for (int i = k + 1; i <= last; ++i) Band(i, j) -= Band(i, k) * upper;
    }
  }
  Eigen::MatrixXd& b = *rhs;
  for (int j = 0; j < size; ++j) {
    const int last = std::min(j + kBandwidth, size - 1);
    for (int i = j + 1; i <= last; ++i) b.row(i) -= Band(i, j) * b.row(j);
  }
  for (int j = size - 1; j >= 0; --j) {
    b.row(j) /= Band(j, j);
    const int first = std::max(0, j - kBandwidth);
    for (int i = first; i < j; ++i) b.row(i) -= Band(i, j) * b.row(j);
  }
}

// M^T x = r with M = L U: U^T z = r (forward), then L^T x = z (backward, unit diagonal).
void MinimumJerkPolynomial::SolveTransposed(Eigen::MatrixXd* rhs) const {
  const int size = 6 * num_pieces_;
  Eigen::MatrixXd& b = *rhs;
  for (int j = 0; j < size; ++j) {
    const int first = std::max(0, j - kBandwidth);
    for (int i = first; i < j; ++i) b.row(j) -= Band(i, j) * b.row(i);
    b.row(j) /= Band(j, j);
  }
  for (int j = size - 1; j >= 0; --j) {
    const int last = std::min(j + kBandwidth, size - 1);
    for (int i = j + 1; i <= last; ++i) b.row(j) -= Band(i, j) * b.row(i);
  }
}

Eigen::RowVectorXd MinimumJerkPolynomial::Evaluate(int piece, double t_s, int derivative) const {
  return Basis(t_s, derivative) * coefficients_.middleRows<6>(6 * piece);
}

double MinimumJerkPolynomial::Energy(const Eigen::VectorXd& weights) const {
  double energy = 0.0;
  for (int i = 0; i < num_pieces_; ++i) {
    const double t1 = durations_(i), t2 = t1 * t1, t3 = t2 * t1, t4 = t3 * t1, t5 = t4 * t1;
    for (int d = 0; d < dimensions(); ++d) {
      const double c3 = coefficients_(6 * i + 3, d), c4 = coefficients_(6 * i + 4, d),
                   c5 = coefficients_(6 * i + 5, d);
      energy += weights(d) * (36.0 * c3 * c3 * t1 + 144.0 * c3 * c4 * t2 + 192.0 * c4 * c4 * t3 +
                              240.0 * c3 * c5 * t3 + 720.0 * c4 * c5 * t4 + 720.0 * c5 * c5 * t5);
    }
  }
  return energy;
}

void MinimumJerkPolynomial::AddEnergyGradient(const Eigen::VectorXd& weights,
                                              Eigen::MatrixXd* dK_dc,
                                              Eigen::VectorXd* dK_dT) const {
  for (int i = 0; i < num_pieces_; ++i) {
    const double t1 = durations_(i), t2 = t1 * t1, t3 = t2 * t1, t4 = t3 * t1, t5 = t4 * t1;
    for (int d = 0; d < dimensions(); ++d) {
      const double w = weights(d);
      const double c3 = coefficients_(6 * i + 3, d), c4 = coefficients_(6 * i + 4, d),
                   c5 = coefficients_(6 * i + 5, d);
      (*dK_dc)(6 * i + 3, d) += w * (72.0 * c3 * t1 + 144.0 * c4 * t2 + 240.0 * c5 * t3);
      (*dK_dc)(6 * i + 4, d) += w * (144.0 * c3 * t2 + 384.0 * c4 * t3 + 720.0 * c5 * t4);
      (*dK_dc)(6 * i + 5, d) += w * (240.0 * c3 * t3 + 720.0 * c4 * t4 + 1440.0 * c5 * t5);
      (*dK_dT)(i) += w * (36.0 * c3 * c3 + 288.0 * c3 * c4 * t1 + 576.0 * c4 * c4 * t2 +
                          720.0 * c3 * c5 * t2 + 2880.0 * c4 * c5 * t3 + 3600.0 * c5 * c5 * t4);
    }
  }
}

void MinimumJerkPolynomial::PropagateGradient(const Eigen::MatrixXd& dK_dc,
                                              const Eigen::VectorXd& dK_dT_partial,
                                              Eigen::MatrixXd* dK_dq, Eigen::VectorXd* dK_dT,
                                              Eigen::MatrixXd* dK_dhead,
                                              Eigen::MatrixXd* dK_dtail) const {
  const int n = num_pieces_;
  // G = M^-T dK/dc is dK/db: b holds the waypoints and the boundary states
  Eigen::MatrixXd adjoint = dK_dc;
  SolveTransposed(&adjoint);
  if (dK_dq != nullptr) {
    dK_dq->resize(n - 1, dimensions());
    for (int i = 0; i < n - 1; ++i) dK_dq->row(i) = adjoint.row(6 * i + 5);
  }
  if (dK_dhead != nullptr) *dK_dhead = adjoint.topRows(3);
  if (dK_dtail != nullptr) *dK_dtail = adjoint.bottomRows(3);
  if (dK_dT == nullptr) return;
  // dc/dT_i = -M^-1 (dM/dT_i) c: dM/dT_i c holds the derivatives at the end of piece i, one order
  // above those of M's rows for that piece
  *dK_dT = dK_dT_partial;
  for (int i = 0; i < n; ++i) {
    const double t = durations_(i);
    auto at_end = [&](int derivative) { return Evaluate(i, t, derivative); };
    double implicit = 0.0;
    if (i < n - 1) {
      const int r = 6 * i;
      implicit += adjoint.row(r + 3).dot(at_end(4));
      implicit += adjoint.row(r + 4).dot(at_end(5));
      implicit += adjoint.row(r + 5).dot(at_end(1));
      implicit += adjoint.row(r + 6).dot(at_end(1));
      implicit += adjoint.row(r + 7).dot(at_end(2));
      implicit += adjoint.row(r + 8).dot(at_end(3));
    } else {
      const int r = 6 * n - 3;
      implicit += adjoint.row(r).dot(at_end(1));
      implicit += adjoint.row(r + 1).dot(at_end(2));
      implicit += adjoint.row(r + 2).dot(at_end(3));
    }
    (*dK_dT)(i) -= implicit;
  }
}

}  // namespace trav::planner
