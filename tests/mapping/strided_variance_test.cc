#include "mapping/strided_variance.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "common/random.h"

namespace trav::mapping {
namespace {

// A GP on 40 random points of [0, 1]^2 and the cells of an 8 x 8 window from (10, 20) to
// (17, 27), cell (ix, iy) at input (0.1 (ix - 10), 0.1 (iy - 20)), without cell (12, 22), a
// lattice corner for stride 2.
class StridedVarianceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    common::Random random(5);
    Eigen::MatrixXd inputs(40, 2);
    Eigen::VectorXd heights(40);
    for (int i = 0; i < 40; ++i) {
      inputs.row(i) << random.Uniform(0.0, 1.0), random.Uniform(0.0, 1.0);
      heights[i] = std::sin(3.0 * inputs(i, 0)) + 0.2 * random.Normal();
    }
    GpHyperparameters hyper;
    hyper.length_scales = Eigen::Vector4d::Constant(0.2);
    ASSERT_TRUE(gp_.Fit(inputs, heights, hyper));
    for (int ix = kLow.x(); ix <= kHigh.x(); ++ix) {
      for (int iy = kLow.y(); iy <= kHigh.y(); ++iy) {
        if (ix != 12 || iy != 22) cells_.emplace_back(ix, iy);
      }
    }
    test_.resize(static_cast<Eigen::Index>(cells_.size()), 2);
    for (std::size_t k = 0; k < cells_.size(); ++k) {
      test_.row(static_cast<Eigen::Index>(k)) << 0.1 * (cells_[k].x() - kLow.x()),
          0.1 * (cells_[k].y() - kLow.y());
    }
    exact_.resize(test_.rows());
    gp_.PredictVariance(test_, exact_);
  }

  // The row of cell (ix, iy), or -1.
  Eigen::Index RowOf(int ix, int iy) const {
    for (std::size_t k = 0; k < cells_.size(); ++k) {
      if (cells_[k] == Eigen::Vector2i(ix, iy)) return static_cast<Eigen::Index>(k);
    }
    return -1;
  }

  static inline const Eigen::Vector2i kLow{10, 20};
  static inline const Eigen::Vector2i kHigh{17, 27};
  SparseGp gp_;
  std::vector<Eigen::Vector2i> cells_;
  Eigen::MatrixXd test_;
  Eigen::VectorXd exact_;
};

TEST_F(StridedVarianceTest, StrideOneIsTheExactVarianceOfEveryCell) {
  StridedVariance dut;
  Eigen::VectorXd variance(test_.rows());
  dut.Compute(gp_, cells_, test_, kLow, kHigh, 1, variance);
  for (Eigen::Index t = 0; t < test_.rows(); ++t) EXPECT_EQ(variance[t], exact_[t]) << t;
}

TEST_F(StridedVarianceTest, EachBlockSharesItsCornersExactVarianceOrThePriorWithoutIt) {
  StridedVariance dut;
  Eigen::VectorXd variance(test_.rows());
  for (const int stride : {2, 4}) {
    dut.Compute(gp_, cells_, test_, kLow, kHigh, stride, variance);
    int prior_cells = 0;
    for (std::size_t k = 0; k < cells_.size(); ++k) {
      const Eigen::Vector2i& cell = cells_[k];
      const Eigen::Index corner = RowOf(cell.x() - cell.x() % stride, cell.y() - cell.y() % stride);
      const double expected = corner >= 0 ? exact_[corner] : gp_.prior_variance();
      prior_cells += corner < 0 ? 1 : 0;
      EXPECT_EQ(variance[static_cast<Eigen::Index>(k)], expected)
          << "stride " << stride << " cell " << cell.transpose();
    }
    // stride 2: the block of the missing corner (12, 22) less the corner itself; stride 4: the
    // columns 10 and 11, whose corner (column 8) is left of the window
    EXPECT_EQ(prior_cells, stride == 2 ? 3 : 16) << "stride " << stride;
  }
  // the variance grows away from the data: the exact values differ, so sharing is visible
  EXPECT_NE(exact_[RowOf(10, 20)], exact_[RowOf(11, 20)]);
}

}  // namespace
}  // namespace trav::mapping
