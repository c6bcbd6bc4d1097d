#include "mapping/strided_variance.h"

#include <cmath>
#include <limits>

#include "common/check.h"

namespace trav::mapping {

void StridedVariance::Compute(const SparseGp& gp, const std::vector<Eigen::Vector2i>& cells,
                              const Eigen::Ref<const Eigen::MatrixXd>& test_inputs,
                              const Eigen::Vector2i& low, const Eigen::Vector2i& high, int stride,
                              Eigen::Ref<Eigen::VectorXd> variance) {
  const auto t_count = static_cast<Eigen::Index>(cells.size());
  TRAV_DEMAND(stride >= 1);
  TRAV_DEMAND(test_inputs.rows() == t_count && variance.size() == t_count);
  sampled_.clear();
  for (Eigen::Index t = 0; t < t_count; ++t) {
    const Eigen::Vector2i& cell = cells[static_cast<std::size_t>(t)];
    if (cell.x() % stride == 0 && cell.y() % stride == 0) sampled_.push_back(t);
  }
  const auto sampled_count = static_cast<Eigen::Index>(sampled_.size());
  auto sampled_inputs = sampled_inputs_.Resize(sampled_count, test_inputs.cols());
  for (Eigen::Index k = 0; k < sampled_count; ++k)
    sampled_inputs.row(k) = test_inputs.row(sampled_[static_cast<std::size_t>(k)]);
  auto sampled_variance = sampled_variance_.Resize(sampled_count);
  gp.PredictVariance(sampled_inputs, sampled_variance);
  // the sampled variances on the window's cells (NaN elsewhere), indexed from `low`
  const Eigen::Vector2i window_size = high - low + Eigen::Vector2i::Ones();
  auto block_variance = block_variance_.Resize(window_size.x(), window_size.y());
  block_variance.setConstant(std::numeric_limits<double>::quiet_NaN());
  for (Eigen::Index k = 0; k < sampled_count; ++k) {
    const Eigen::Vector2i& cell =
        cells[static_cast<std::size_t>(sampled_[static_cast<std::size_t>(k)])];
    block_variance(cell.x() - low.x(), cell.y() - low.y()) = sampled_variance[k];
  }
  for (Eigen::Index t = 0; t < t_count; ++t) {
    const Eigen::Vector2i& cell = cells[static_cast<std::size_t>(t)];
    const Eigen::Vector2i corner =
        Eigen::Vector2i(cell.x() - cell.x() % stride, cell.y() - cell.y() % stride) - low;
    const double v = (corner.array() >= 0).all() ? block_variance(corner.x(), corner.y())
                                                 : std::numeric_limits<double>::quiet_NaN();
    // a block whose corner cell is unsupported: the prior variance (least certain)
    variance[t] = std::isnan(v) ? gp.prior_variance() : v;
  }
}

}  // namespace trav::mapping
