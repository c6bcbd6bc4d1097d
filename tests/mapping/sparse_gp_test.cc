#include "mapping/sparse_gp.h"

#include <cmath>
#include <tuple>
#include <vector>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "common/random.h"

namespace trav::mapping {
namespace {

// Random inputs in [-1, 1]^dims and smooth heights.
void MakeData(int n, int dims, Eigen::MatrixXd* inputs, Eigen::VectorXd* heights) {
  common::Random random(3);
  inputs->resize(n, dims);
  heights->resize(n);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < dims; ++d) (*inputs)(i, d) = random.Uniform(-1.0, 1.0);
    (*heights)[i] =
        std::sin(2.0 * (*inputs)(i, 0)) + 0.5 * (*inputs)(i, 1) + 0.05 * random.Normal();
  }
}

GpHyperparameters Hyper(KernelType kernel) {
  GpHyperparameters hyper;
  hyper.kernel = kernel;
  hyper.length_scales = Eigen::Vector4d(0.5, 0.7, 0.9, 1.1);
  hyper.signal_variance_ratio = 1.3;
  hyper.noise_std_m = 0.1;
  hyper.rq_alpha = 1.7;
  return hyper;
}

// theta = (log l_1..4, log ratio, log s_n^2, log alpha)
GpHyperparameters Perturbed(GpHyperparameters hyper, int index, double delta) {
  if (index < 4) hyper.length_scales[index] *= std::exp(delta);
  if (index == 4) hyper.signal_variance_ratio *= std::exp(delta);
  if (index == 5) hyper.noise_std_m *= std::exp(0.5 * delta);
  if (index == 6) hyper.rq_alpha *= std::exp(delta);
  return hyper;
}

TEST(SparseGpTest, LikelihoodGradientMatchesFiniteDifferences) {
  Eigen::MatrixXd inputs;
  Eigen::VectorXd heights;
  MakeData(40, 4, &inputs, &heights);
  for (KernelType kernel : {KernelType::kSquaredExponential, KernelType::kRationalQuadratic}) {
    const GpHyperparameters hyper = Hyper(kernel);
    Eigen::VectorXd gradient;
    SparseGp::LogMarginalLikelihood(inputs, heights, hyper, &gradient);
    ASSERT_EQ(gradient.size(), 7);
    const double h = 1e-5;
    for (int j = 0; j < 7; ++j) {
      const double up =
          SparseGp::LogMarginalLikelihood(inputs, heights, Perturbed(hyper, j, h), nullptr);
      const double down =
          SparseGp::LogMarginalLikelihood(inputs, heights, Perturbed(hyper, j, -h), nullptr);
      const double numeric = (up - down) / (2 * h);
      EXPECT_NEAR(gradient[j], kernel == KernelType::kSquaredExponential && j == 6 ? 0.0 : numeric,
                  1e-5 * std::max(1.0, std::abs(numeric)))
          << "parameter " << j;
    }
  }
}

TEST(SparseGpTest, MeanGradientMatchesFiniteDifferences) {
  Eigen::MatrixXd inputs;
  Eigen::VectorXd heights;
  MakeData(60, 4, &inputs, &heights);
  for (KernelType kernel : {KernelType::kSquaredExponential, KernelType::kRationalQuadratic}) {
    SparseGp dut;
    ASSERT_TRUE(dut.Fit(inputs, heights, Hyper(kernel)));
    Eigen::MatrixXd test(3, 4);
    test << 0.1, -0.2, 0.3, 0.0, -0.5, 0.4, -0.1, 0.2, 0.7, 0.7, 0.5, -0.5;
    Eigen::VectorXd mean(test.rows()), variance(test.rows());
    Eigen::MatrixXd gradient(test.rows(), test.cols());
    dut.Predict(test, mean, gradient);
    dut.PredictVariance(test, variance);
    const double h = 1e-6;
    for (int d = 0; d < 4; ++d) {
      Eigen::MatrixXd up = test, down = test;
      up.col(d).array() += h;
      down.col(d).array() -= h;
      Eigen::VectorXd mean_up(3), mean_down(3);
      Eigen::MatrixXd unused_gradient(3, 4);
      dut.Predict(up, mean_up, unused_gradient);
      dut.Predict(down, mean_down, unused_gradient);
      for (int t = 0; t < 3; ++t)
        EXPECT_NEAR(gradient(t, d), (mean_up[t] - mean_down[t]) / (2 * h), 1e-6);
    }
    EXPECT_TRUE((variance.array() >= 0.0).all());
  }
}

// On a lattice of test points the factorised kernel gives Predict's mean and gradient to within
// rounding, with the same neighbours (the cutoff) and a gradient that matches finite differences.
TEST(SparseGpTest, PredictionOnALatticeEqualsPredictWithinRounding) {
  Eigen::MatrixXd inputs;
  Eigen::VectorXd heights;
  MakeData(200, 2, &inputs, &heights);
  inputs *= 3.0;  // over [-3, 3]^2 with length scales 0.5 and 0.7: the cutoff (7.1 l) bites
  SparseGp dut;
  ASSERT_TRUE(dut.Fit(inputs, heights, Hyper(KernelType::kSquaredExponential)));
  // a 31 x 25 lattice reaching beyond the data, in the order a map's cells are visited
  Eigen::MatrixXd test(31 * 25, 2);
  for (int ix = 0; ix < 31; ++ix) {
    for (int iy = 0; iy < 25; ++iy) test.row(ix * 25 + iy) << -7.5 + 0.5 * ix, -6.0 + 0.5 * iy;
  }
  Eigen::VectorXd mean(test.rows()), lattice_mean(test.rows());
  Eigen::MatrixXd gradient(test.rows(), 2), lattice_gradient(test.rows(), 2);
  dut.Predict(test, mean, gradient);
  dut.PredictOnLattice(test, lattice_mean, lattice_gradient);
  int beyond_the_data = 0;
  for (Eigen::Index t = 0; t < test.rows(); ++t) {
    EXPECT_NEAR(lattice_mean[t], mean[t], 1e-12 * (1.0 + std::abs(mean[t]))) << t;
    for (int d = 0; d < 2; ++d) {
      EXPECT_NEAR(lattice_gradient(t, d), gradient(t, d), 1e-12 * (1.0 + std::abs(gradient(t, d))));
    }
    // far from every training point no neighbour counts: the prior mean exactly, in both
    if (lattice_gradient.row(t).isZero() && gradient.row(t).isZero()) {
      EXPECT_EQ(lattice_mean[t], mean[t]);
      ++beyond_the_data;
    }
  }
  EXPECT_GT(beyond_the_data, 0);
  // the gradient against the mean's finite differences at an off-lattice pair of points
  Eigen::MatrixXd pair(2, 2);
  pair << 0.3, -0.45, 0.3, -0.45;
  const double h = 1e-6;
  for (int d = 0; d < 2; ++d) {
    pair(1, d) += h;
    Eigen::VectorXd pair_mean(2);
    Eigen::MatrixXd pair_gradient(2, 2);
    dut.PredictOnLattice(pair, pair_mean, pair_gradient);
    EXPECT_NEAR(pair_gradient(0, d), (pair_mean[1] - pair_mean[0]) / h, 1e-5);
    pair(1, d) -= h;
  }
}

// The compact-support kernel, the envelope factor (squared exponential) and the mixed-precision
// dense factor (rational quadratic) against the textbook equations in double precision on dense
// matrices: length scales short enough that most pairs fall beyond the squared exponential's
// cutoff.
TEST(SparseGpTest, MatchesTheDenseDoublePrecisionEquations) {
  Eigen::MatrixXd inputs;
  Eigen::VectorXd heights;
  MakeData(300, 4, &inputs, &heights);
  Eigen::MatrixXd test(50, 4);
  common::Random random(11);
  for (Eigen::Index i = 0; i < test.size(); ++i) test.data()[i] = random.Uniform(-1.1, 1.1);
  // (kernel, x-y length scale, the factor Fit must choose: envelope or dense); a length scale of
  // 0.5 puts the cutoff beyond the inputs' extent
  const std::vector<std::tuple<KernelType, double, bool>> cases = {
      {KernelType::kSquaredExponential, 0.08, true},
      {KernelType::kSquaredExponential, 0.5, false},
      {KernelType::kRationalQuadratic, 0.08, false}};
  for (const auto& [kernel, length_scale, envelope] : cases) {
    GpHyperparameters hyper = Hyper(kernel);
    hyper.length_scales = Eigen::Vector4d(length_scale, 1.25 * length_scale, 2.0, 2.0);
    hyper.noise_std_m = 0.03;
    SparseGp dut;
    ASSERT_TRUE(dut.Fit(inputs, heights, hyper));
    EXPECT_EQ(dut.envelope_factor(), envelope) << length_scale;
    Eigen::VectorXd mean(test.rows()), variance(test.rows());
    Eigen::MatrixXd gradient(test.rows(), test.cols());
    dut.Predict(test, mean, gradient);
    dut.PredictVariance(test, variance);

    const double s2 = dut.prior_variance();
    auto k = [&](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
      Eigen::MatrixXd out(a.rows(), b.rows());
      for (Eigen::Index i = 0; i < a.rows(); ++i)
        for (Eigen::Index j = 0; j < b.rows(); ++j)
          out(i, j) = SparseGp::Kernel(hyper, s2, a.row(i), b.row(j));
      return out;
    };
    Eigen::MatrixXd k_mm = k(inputs, inputs);
    k_mm.diagonal().array() += hyper.noise_std_m * hyper.noise_std_m;
    const Eigen::LLT<Eigen::MatrixXd> llt(k_mm);
    const Eigen::MatrixXd k_tm = k(test, inputs);
    const Eigen::VectorXd expected_mean =
        (k_tm * llt.solve((heights.array() - heights.mean()).matrix())).array() + heights.mean();
    const Eigen::VectorXd expected_variance =
        s2 - (k_tm * llt.solve(k_tm.transpose())).diagonal().array();
    EXPECT_LT((mean - expected_mean).cwiseAbs().maxCoeff(), 1e-9)
        << static_cast<int>(kernel) << " " << length_scale;
    EXPECT_LT((variance - expected_variance).cwiseAbs().maxCoeff(), (envelope ? 1e-9 : 1e-5) * s2)
        << static_cast<int>(kernel) << " " << length_scale;
  }
}

TEST(SparseGpTest, InterpolatesASmoothSurfaceWithinABound) {
  // z = 0.3 sin(x) cos(0.5 y) sampled on 300 points over 6 x 6 m, predicted on a grid
  common::Random random(5);
  Eigen::MatrixXd inputs(300, 2);
  Eigen::VectorXd heights(300);
  auto surface = [](double x, double y) { return 0.3 * std::sin(x) * std::cos(0.5 * y); };
  for (int i = 0; i < 300; ++i) {
    inputs.row(i) << random.Uniform(-3, 3), random.Uniform(-3, 3);
    heights[i] = surface(inputs(i, 0), inputs(i, 1));
  }
  GpHyperparameters hyper;
  hyper.length_scales = Eigen::Vector4d(1.0, 1.0, 1.0, 1.0);
  hyper.noise_std_m = 0.005;
  SparseGp dut;
  ASSERT_TRUE(dut.Fit(inputs, heights, hyper));
  Eigen::MatrixXd test(121, 2);
  for (int i = 0; i < 11; ++i) {
    for (int j = 0; j < 11; ++j) test.row(11 * i + j) << -2.5 + 0.5 * i, -2.5 + 0.5 * j;
  }
  Eigen::VectorXd mean(test.rows());
  Eigen::MatrixXd gradient(test.rows(), test.cols());
  dut.Predict(test, mean, gradient);
  double worst = 0.0;
  for (int t = 0; t < 121; ++t)
    worst = std::max(worst, std::abs(mean[t] - surface(test(t, 0), test(t, 1))));
  EXPECT_LT(worst, 0.01);  // 1 cm on a 30 cm relief
}

TEST(SparseGpTest, OptimisingRaisesTheLikelihood) {
  Eigen::MatrixXd inputs;
  Eigen::VectorXd heights;
  MakeData(50, 4, &inputs, &heights);
  GpHyperparameters hyper = Hyper(KernelType::kSquaredExponential);
  hyper.length_scales = Eigen::Vector4d(3.0, 3.0, 3.0, 3.0);
  const double before = SparseGp::LogMarginalLikelihood(inputs, heights, hyper, nullptr);
  EXPECT_GT(SparseGp::OptimiseHyperparameters(inputs, heights, 5, &hyper), 0);
  EXPECT_GT(SparseGp::LogMarginalLikelihood(inputs, heights, hyper, nullptr), before);
}

}  // namespace
}  // namespace trav::mapping
