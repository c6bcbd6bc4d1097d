#include "mapping/envelope_cholesky.h"

#include <algorithm>
#include <vector>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "common/random.h"

namespace trav::mapping {
namespace {

// Fills `dut` with the lower triangle of `a` within the envelope `first`.
void Fill(const Eigen::MatrixXd& a, const std::vector<int>& first, EnvelopeCholesky* dut) {
  dut->Reset(first);
  for (int i = 0; i < static_cast<int>(first.size()); ++i)
    for (int j = first[static_cast<std::size_t>(i)]; j <= i; ++j) (*dut)(i, j) = a(i, j);
}

// A random symmetric positive definite matrix whose row i is zero before column first[i]: random
// entries within the envelope, made diagonally dominant.
Eigen::MatrixXd RandomEnvelopeMatrix(const std::vector<int>& first, common::Random* random) {
  const auto n = static_cast<Eigen::Index>(first.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = first[static_cast<std::size_t>(i)]; j < i; ++j) {
      a(i, j) = random->Uniform(-1.0, 1.0);
      a(j, i) = a(i, j);
    }
  }
  for (Eigen::Index i = 0; i < n; ++i) a(i, i) = a.row(i).cwiseAbs().sum() + 0.5;
  return a;
}

TEST(EnvelopeCholeskyTest, FactorisesATridiagonalMatrixExactly) {
  // [4 2 0; 2 5 2; 0 2 5] = L L^T with L = [2 0 0; 1 2 0; 0 1 2]
  Eigen::Matrix3d a;
  a << 4, 2, 0, 2, 5, 2, 0, 2, 5;
  EnvelopeCholesky dut;
  Fill(a, {0, 0, 1}, &dut);
  EXPECT_EQ(dut.stored(), 5U);
  ASSERT_TRUE(dut.Factorize());
  EXPECT_EQ(dut(0, 0), 2.0);
  EXPECT_EQ(dut(1, 0), 1.0);
  EXPECT_EQ(dut(1, 1), 2.0);
  EXPECT_EQ(dut(2, 1), 1.0);
  EXPECT_EQ(dut(2, 2), 2.0);
  // A x = (6, 9, 7) for x = (1, 1, 1)
  Eigen::VectorXd b(3);
  b << 6, 9, 7;
  dut.Solve(b);
  EXPECT_NEAR((b - Eigen::Vector3d::Ones()).cwiseAbs().maxCoeff(), 0.0, 1e-15);
}

TEST(EnvelopeCholeskyTest, MatchesTheDenseFactorOnRandomEnvelopes) {
  common::Random random(7);
  for (int trial = 0; trial < 5; ++trial) {
    const int n = 40 + 15 * trial;
    std::vector<int> first(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const int width = static_cast<int>(random.UniformIndex(12));
      first[static_cast<std::size_t>(i)] = std::max(0, i - width);
    }
    const Eigen::MatrixXd a = RandomEnvelopeMatrix(first, &random);
    const Eigen::LLT<Eigen::MatrixXd> llt(a);
    ASSERT_EQ(llt.info(), Eigen::Success);
    const Eigen::MatrixXd l = llt.matrixL();

    EnvelopeCholesky dut;
    Fill(a, first, &dut);
    ASSERT_TRUE(dut.Factorize());
    for (int i = 0; i < n; ++i) {
      // nothing of the dense factor lies before a row's envelope
      for (int j = 0; j < first[static_cast<std::size_t>(i)]; ++j) EXPECT_EQ(l(i, j), 0.0);
      for (int j = first[static_cast<std::size_t>(i)]; j <= i; ++j)
        EXPECT_NEAR(dut(i, j), l(i, j), 1e-12) << i << ", " << j;
    }

    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) b[i] = random.Uniform(-1.0, 1.0);
    const Eigen::VectorXd expected = llt.solve(b);
    Eigen::VectorXd x = b;
    dut.Solve(x);
    EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-12);

    // b^T A^-1 b for a right-hand side whose first entries are zero, from its first nonzero
    const int first_nonzero = n / 3;
    b.head(first_nonzero).setZero();
    const double expected_norm = b.dot(llt.solve(b));
    Eigen::VectorXd y = b;
    EXPECT_NEAR(dut.SolveLowerSquaredNorm(y, first_nonzero), expected_norm, 1e-12 * expected_norm);
    EXPECT_LT((l * y - b).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(EnvelopeCholeskyTest, RefusesAMatrixThatIsNotPositiveDefinite) {
  Eigen::Matrix2d a;
  a << 1, 2, 2, 1;
  EnvelopeCholesky dut;
  Fill(a, {0, 0}, &dut);
  EXPECT_FALSE(dut.Factorize());
  a(1, 1) = 4.0;  // positive semi-definite: a zero pivot
  Fill(a, {0, 0}, &dut);
  EXPECT_FALSE(dut.Factorize());
}

TEST(EnvelopeCholeskyTest, ResetClearsTheEntriesOfAnEarlierMatrix) {
  common::Random random(3);
  EnvelopeCholesky dut;
  const std::vector<int> dense = {0, 0, 0, 0};
  Fill(RandomEnvelopeMatrix(dense, &random), dense, &dut);
  ASSERT_TRUE(dut.Factorize());
  // a diagonal matrix in a tridiagonal envelope: the off-diagonal entries must read zero
  dut.Reset({0, 0, 1, 2});
  for (int i = 0; i < 4; ++i) dut(i, i) = 4.0;
  ASSERT_TRUE(dut.Factorize());
  for (int i = 1; i < 4; ++i) EXPECT_EQ(dut(i, i - 1), 0.0);
  EXPECT_EQ(dut(3, 3), 2.0);
}

}  // namespace
}  // namespace trav::mapping
