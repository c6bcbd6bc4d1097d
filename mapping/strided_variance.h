#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/scratch.h"
#include "mapping/sparse_gp.h"

namespace trav::mapping {

/// A GP's predictive variance on a window's cells, computed exactly on a lattice and shared by the
/// blocks around it: the cells whose indices are both multiples of `stride` get
/// SparseGp::PredictVariance, every other cell the value of the lattice cell at the lower corner
/// of its stride x stride block, or the GP's prior variance (the least certain) when that corner
/// is not among the cells. The variance is the costly part of a GP's prediction (O(T M^2) against
/// O(T M) for the mean); on a lattice it costs stride^2 times less. Every GP mapper's variance
/// layer is made this way (FSGP-BGK weighs its fusion with it; SGP only writes it). Reuses its
/// storage between calls.
class StridedVariance {
 public:
  /// The variance of `gp` at `cells` (grid indices, each within [low, high]), whose GP inputs are
  /// the rows of `test_inputs` (one per cell, as SparseGp::PredictVariance takes them), into
  /// `variance` (sized by the caller: one per cell). `stride` >= 1 (1: every cell exactly).
  void Compute(const SparseGp& gp, const std::vector<Eigen::Vector2i>& cells,
               const Eigen::Ref<const Eigen::MatrixXd>& test_inputs, const Eigen::Vector2i& low,
               const Eigen::Vector2i& high, int stride, Eigen::Ref<Eigen::VectorXd> variance);

 private:
  std::vector<Eigen::Index> sampled_;
  common::ScratchMatrix<double> sampled_inputs_;
  common::ScratchMatrix<double, Eigen::Dynamic, 1> sampled_variance_;
  common::ScratchMatrix<double> block_variance_;
};

}  // namespace trav::mapping
