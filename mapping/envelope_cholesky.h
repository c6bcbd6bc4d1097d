#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace trav::mapping {

/// The Cholesky factor L (A = L L^T) of a symmetric positive definite n x n matrix stored by its
/// envelope (Jennings' profile storage): row i keeps its lower-triangle entries from a first
/// column f(i) <= i to the diagonal, contiguously. Fill-in never leaves the envelope, so a matrix
/// whose nonzeros lie near the diagonal costs sum_i (i - f(i))^2 / 2 multiply-adds to factorise
/// instead of n^3 / 6, and a forward solve sum_i (i - f(i)). A compact-support kernel over points
/// ordered along an axis is such a matrix: each row reaches back only to the first point within
/// the kernel's support along that axis.
///
/// Written here, not taken from a library: Eigen's SimplicialLLT and CHOLMOD allocate in every
/// analysis and factorisation, which the mapper may not do per frame (mapping/README.md), and a
/// sparse solver's fill-reducing orderings buy little over an axis order for a kernel on a
/// window of a few hundred points. The forward solve that starts at a right-hand side's first
/// nonzero (SolveLowerSquaredNorm) is what the GP's predictive variance needs.
class EnvelopeCholesky {
 public:
  /// Starts a matrix of n = first_column.size() rows, row i's envelope from column
  /// first_column[i] (0 <= first_column[i] <= i) to the diagonal, every entry zero. Reuses the
  /// storage: nothing is allocated once a matrix of n rows has been seen (the storage of the full
  /// lower triangle is kept).
  void Reset(const std::vector<int>& first_column);

  /// Entry (i, j) of the lower triangle, first_column[i] <= j <= i (checked).
  /// Before Factorize: the matrix; after: the factor.
  double& operator()(int i, int j);

  /// Factorises in place. @returns false, the factor then unusable, if the matrix is not
  /// positive definite (a pivot not above zero, or not finite).
  bool Factorize();

  /// Solves A x = b in place (after a successful Factorize).
  void Solve(Eigen::Ref<Eigen::VectorXd> b) const;

  /// Overwrites b with L^-1 b and returns its squared norm, b^T A^-1 b. The entries of b before
  /// `first_nonzero` must be zero: the solve starts there (after a successful Factorize).
  double SolveLowerSquaredNorm(Eigen::Ref<Eigen::VectorXd> b, int first_nonzero) const;

  /// The number of rows n.
  int size() const { return static_cast<int>(first_.size()); }
  /// The stored entries, sum_i (i - f(i) + 1).
  std::size_t stored() const { return values_.size(); }

 private:
  // Row i's entries, columns first_[i] .. i.
  double* Row(int i) { return values_.data() + start_[static_cast<std::size_t>(i)]; }
  const double* Row(int i) const { return values_.data() + start_[static_cast<std::size_t>(i)]; }
  int First(int i) const { return first_[static_cast<std::size_t>(i)]; }

  std::vector<int> first_;          // each row's first column
  std::vector<std::size_t> start_;  // where each row begins in values_ (n + 1 entries)
  std::vector<double> values_;
};

}  // namespace trav::mapping
