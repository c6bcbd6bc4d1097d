#include "planner/minco.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/random.h"

namespace trav::planner {
namespace {

Eigen::MatrixXd RandomMatrix(common::Random* random, int rows, int cols) {
  Eigen::MatrixXd m(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) m(r, c) = random->Uniform(-2.0, 2.0);
  }
  return m;
}

// A random 2-D problem of `pieces` pieces.
struct Problem {
  Eigen::MatrixXd head, tail, inner;
  Eigen::VectorXd durations;
};

Problem RandomProblem(int pieces, std::uint64_t seed) {
  common::Random random(seed);
  Problem p;
  p.head = RandomMatrix(&random, 3, 2);
  p.tail = RandomMatrix(&random, 3, 2);
  p.inner = RandomMatrix(&random, pieces - 1, 2);
  p.durations.resize(pieces);
  for (int i = 0; i < pieces; ++i) p.durations(i) = random.Uniform(0.5, 2.0);
  return p;
}

MinimumJerkPolynomial Solve(const Problem& p) {
  MinimumJerkPolynomial dut;
  dut.SetBoundary(p.head, p.tail, static_cast<int>(p.durations.size()));
  dut.SetParameters(p.inner, p.durations);
  return dut;
}

TEST(MinimumJerkPolynomialTest, MeetsBoundaryStatesAndWaypointsAndIsC4) {
  const Problem p = RandomProblem(6, 1);
  const MinimumJerkPolynomial dut = Solve(p);
  for (int d = 0; d < 3; ++d) {
    EXPECT_TRUE(dut.Evaluate(0, 0.0, d).isApprox(p.head.row(d), 1e-12)) << d;
    EXPECT_TRUE(dut.Evaluate(5, p.durations(5), d).isApprox(p.tail.row(d), 1e-9)) << d;
  }
  for (int i = 0; i < 5; ++i) {
    EXPECT_LT((dut.Evaluate(i, p.durations(i), 0) - p.inner.row(i)).norm(), 1e-9) << i;
    for (int d = 0; d <= 4; ++d) {
      const Eigen::RowVectorXd end = dut.Evaluate(i, p.durations(i), d);
      const Eigen::RowVectorXd start = dut.Evaluate(i + 1, 0.0, d);
      EXPECT_LT((end - start).norm(), 1e-8 * (1.0 + end.norm())) << "junction " << i << " d" << d;
    }
  }
}

TEST(MinimumJerkPolynomialTest, OnePieceRestToRestIsTheClosedFormMinimumJerk) {
  // p(t) = p0 + (p1 - p0)(10 u^3 - 15 u^4 + 6 u^5), u = t / T; energy 720 |p1 - p0|^2 / T^5
  const double duration = 2.5;
  Eigen::MatrixXd head = Eigen::MatrixXd::Zero(3, 2), tail = Eigen::MatrixXd::Zero(3, 2);
  head.row(0) << 1.0, -2.0;
  tail.row(0) << 4.0, 2.0;
  MinimumJerkPolynomial dut;
  dut.SetBoundary(head, tail, 1);
  dut.SetParameters(Eigen::MatrixXd(0, 2), Eigen::VectorXd::Constant(1, duration));
  for (double t = 0.0; t <= duration; t += 0.25) {
    const double u = t / duration;
    const Eigen::RowVector2d expected =
        head.row(0) + (tail.row(0) - head.row(0)) *
                          (10 * std::pow(u, 3) - 15 * std::pow(u, 4) + 6 * std::pow(u, 5));
    EXPECT_LT((dut.Evaluate(0, t, 0) - expected).norm(), 1e-12) << t;
  }
  const double energy = dut.Energy(Eigen::Vector2d(1.0, 1.0));
  EXPECT_NEAR(energy, 720.0 * 25.0 / std::pow(duration, 5), 1e-9);
}

TEST(MinimumJerkPolynomialTest, WaypointsOnTheOptimalCurveReproduceIt) {
  // the minimum-jerk curve through no waypoints is optimal for any waypoints sampled from it
  const Problem p = RandomProblem(1, 2);
  MinimumJerkPolynomial single;
  single.SetBoundary(p.head, p.tail, 1);
  single.SetParameters(Eigen::MatrixXd(0, 2), Eigen::VectorXd::Constant(1, 3.0));
  Eigen::MatrixXd inner(2, 2);
  inner.row(0) = single.Evaluate(0, 0.8, 0);
  inner.row(1) = single.Evaluate(0, 2.1, 0);
  MinimumJerkPolynomial dut;
  dut.SetBoundary(p.head, p.tail, 3);
  dut.SetParameters(inner, Eigen::Vector3d(0.8, 1.3, 0.9));
  for (double t = 0.0; t <= 3.0; t += 0.1) {
    const int piece = t < 0.8 ? 0 : (t < 2.1 ? 1 : 2);
    const double local = t - (piece == 0 ? 0.0 : (piece == 1 ? 0.8 : 2.1));
    EXPECT_LT((dut.Evaluate(piece, local, 0) - single.Evaluate(0, t, 0)).norm(), 1e-9) << t;
  }
  const Eigen::Vector2d weights(0.33, 1.0);
  EXPECT_NEAR(dut.Energy(weights), single.Energy(weights), 1e-9 * single.Energy(weights));
}

// K(c, T) = weighted energy + a fixed linear function of the coefficients + sum T_i^2.
double TestCost(const MinimumJerkPolynomial& m, const Eigen::MatrixXd& linear) {
  return m.Energy(Eigen::Vector2d(0.33, 1.0)) + (linear.array() * m.coefficients().array()).sum() +
         m.durations().squaredNorm();
}

TEST(MinimumJerkPolynomialTest, PropagatedGradientMatchesFiniteDifferences) {
  const Problem p = RandomProblem(5, 3);
  common::Random random(4);
  const Eigen::MatrixXd linear = RandomMatrix(&random, 30, 2);
  const MinimumJerkPolynomial dut = Solve(p);
  Eigen::MatrixXd dK_dc = linear;
  Eigen::VectorXd dK_dT = 2.0 * p.durations;
  dut.AddEnergyGradient(Eigen::Vector2d(0.33, 1.0), &dK_dc, &dK_dT);
  Eigen::MatrixXd dK_dq, dK_dhead, dK_dtail;
  Eigen::VectorXd dK_dT_total;
  dut.PropagateGradient(dK_dc, dK_dT, &dK_dq, &dK_dT_total, &dK_dhead, &dK_dtail);

  const double h = 1e-6;
  auto central = [&](auto perturb) {
    Problem plus = p, minus = p;
    perturb(&plus, h);
    perturb(&minus, -h);
    return (TestCost(Solve(plus), linear) - TestCost(Solve(minus), linear)) / (2 * h);
  };
  for (int i = 0; i < 4; ++i) {
    for (int d = 0; d < 2; ++d) {
      const double fd = central([&](Problem* q, double e) { q->inner(i, d) += e; });
      EXPECT_NEAR(dK_dq(i, d), fd, 1e-5 * (1.0 + std::abs(fd))) << "q " << i << "," << d;
    }
  }
  for (int i = 0; i < 5; ++i) {
    const double fd = central([&](Problem* q, double e) { q->durations(i) += e; });
    EXPECT_NEAR(dK_dT_total(i), fd, 1e-5 * (1.0 + std::abs(fd))) << "T " << i;
  }
  for (int r = 0; r < 3; ++r) {
    for (int d = 0; d < 2; ++d) {
      const double fd_head = central([&](Problem* q, double e) { q->head(r, d) += e; });
      const double fd_tail = central([&](Problem* q, double e) { q->tail(r, d) += e; });
      EXPECT_NEAR(dK_dhead(r, d), fd_head, 1e-5 * (1.0 + std::abs(fd_head))) << r << "," << d;
      EXPECT_NEAR(dK_dtail(r, d), fd_tail, 1e-5 * (1.0 + std::abs(fd_tail))) << r << "," << d;
    }
  }
}

TEST(MinimumJerkPolynomialTest, RejectsBadShapesAndDurations) {
  MinimumJerkPolynomial dut;
  EXPECT_THROW(dut.SetBoundary(Eigen::MatrixXd::Zero(3, 2), Eigen::MatrixXd::Zero(3, 2), 0),
               std::invalid_argument);
  EXPECT_THROW(dut.SetBoundary(Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Zero(3, 2), 2),
               std::invalid_argument);
  dut.SetBoundary(Eigen::MatrixXd::Zero(3, 2), Eigen::MatrixXd::Zero(3, 2), 2);
  EXPECT_THROW(dut.SetParameters(Eigen::MatrixXd::Zero(1, 2), Eigen::Vector2d(1.0, 0.0)),
               std::invalid_argument);
  EXPECT_THROW(dut.SetParameters(Eigen::MatrixXd::Zero(2, 2), Eigen::Vector2d(1.0, 1.0)),
               std::invalid_argument);
}

}  // namespace
}  // namespace trav::planner
