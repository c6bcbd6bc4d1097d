#pragma once

#include <Eigen/Core>

namespace trav::planner {

/// Minimum-jerk piecewise quintic polynomials (MINCO with s = 3; Wang, Zhou, Xu, Gao,
/// "Geometrically Constrained Trajectory Optimization for Multicopters", IEEE T-RO 38(5), 2022).
///
/// A D-dimensional curve of N pieces: piece i is p_i(t) = sum_k c_{i,k} t^k, k = 0..5, t in [0,
/// T_i]. Given the head and tail position, velocity and acceleration, the N - 1 inner waypoints and
/// the durations T_i, the curve minimising the jerk energy sum_i int ||p_i'''||^2 dt is the unique
/// solution of a banded linear system M(T) c = b(q, head, tail) with C^4 continuity at the inner
/// waypoints. M is 6N x 6N with lower and upper bandwidth 6, factorised in O(N).
///
/// Any cost K(c, T) of the coefficients and durations maps back to the waypoints, durations and
/// boundary states with one solve of the transposed system (`PropagateGradient`), so an optimiser
/// works on (q, T) and never on the coefficients.
class MinimumJerkPolynomial {
 public:
  MinimumJerkPolynomial() = default;

  /// Sets the boundary states and the number of pieces. `head` and `tail` are 3 x D: position,
  /// velocity and acceleration rows. @throws std::invalid_argument if num_pieces < 1 or the shapes
  /// disagree.
  void SetBoundary(const Eigen::MatrixXd& head, const Eigen::MatrixXd& tail, int num_pieces);

  /// Replaces the tail state (3 x D) and keeps everything else; call SetParameters afterwards.
  void SetTail(const Eigen::MatrixXd& tail);

  /// Solves for the coefficients. `inner_points` is (N - 1) x D, waypoint i between pieces i and
  /// i + 1; `durations_s` has N positive entries. @throws std::invalid_argument on shape mismatch
  /// or a non-positive duration.
  void SetParameters(const Eigen::MatrixXd& inner_points, const Eigen::VectorXd& durations_s);

  int num_pieces() const { return num_pieces_; }
  int dimensions() const { return static_cast<int>(head_.cols()); }
  const Eigen::VectorXd& durations() const { return durations_; }

  /// Coefficients, 6N x D: rows 6i .. 6i + 5 are piece i's in ascending powers.
  const Eigen::MatrixXd& coefficients() const { return coefficients_; }

  /// The `derivative` (0 to 5) of piece `piece` at local time t_s in [0, T_piece], 1 x D.
  Eigen::RowVectorXd Evaluate(int piece, double t_s, int derivative) const;

  /// sum_d weights_d sum_i int_0^{T_i} (p_{i,d}''')^2 dt, in closed form.
  double Energy(const Eigen::VectorXd& weights) const;

  /// Adds the partial derivatives of `Energy(weights)` with respect to the coefficients (6N x D)
  /// and the durations (N) at fixed coefficients.
  void AddEnergyGradient(const Eigen::VectorXd& weights, Eigen::MatrixXd* dK_dc,
                         Eigen::VectorXd* dK_dT) const;

  /// Maps the gradient of a cost K(c(q, T, head, tail), T) to the free parameters. `dK_dc` (6N x D)
  /// is its partial derivative with respect to the coefficients, `dK_dT_partial` (N) with respect
  /// to the durations at fixed coefficients. Outputs: dK/dq ((N - 1) x D), the total dK/dT (N), and
  /// dK/d head and dK/d tail (3 x D each: position, velocity, acceleration rows); null outputs are
  /// skipped. One back-solve with the stored factors: O(N).
  void PropagateGradient(const Eigen::MatrixXd& dK_dc, const Eigen::VectorXd& dK_dT_partial,
                         Eigen::MatrixXd* dK_dq, Eigen::VectorXd* dK_dT, Eigen::MatrixXd* dK_dhead,
                         Eigen::MatrixXd* dK_dtail) const;

 private:
  // LU factors of M without pivoting, stored by rows: entry (r, c) at band_(r, c - r + 6).
  void FactorizeAndSolve(Eigen::MatrixXd* rhs);
  void SolveTransposed(Eigen::MatrixXd* rhs) const;
  double& Band(int row, int col) { return band_(row, col - row + kBandwidth); }
  double Band(int row, int col) const { return band_(row, col - row + kBandwidth); }

  static constexpr int kBandwidth = 6;

  int num_pieces_{0};
  Eigen::MatrixXd head_;
  Eigen::MatrixXd tail_;
  Eigen::VectorXd durations_;
  Eigen::MatrixXd band_;  // 6N x 13
  Eigen::MatrixXd coefficients_;
};

}  // namespace trav::planner
