#include "planner/ompl/ompl_planner.h"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/enum_names.h"
#include "planner/astar.h"
#include "planner/cost_map.h"

namespace trav::planner {

// Test names and failure messages print the algorithm's name.
void PrintTo(SamplingAlgorithm algorithm, std::ostream* os) { *os << common::NameOf(algorithm); }

namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

const Eigen::Vector2d kStart(-3.0, 0.0);
const Eigen::Vector2d kGoal(3.0, 0.0);

// A 10 x 10 m map at 0.1 m, free (cost 0) but for a lethal wall at x = 0 from the map's bottom edge
// up to y = 2, inflated by 0.2 m: a path from kStart to kGoal must go round the wall's top end.
common::GridLayers WallMap() {
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(10, 10), 0.1),
      {"traversability"});
  const common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      map.Layer("traversability")(ix, iy) = std::abs(p.x()) < 0.15 && p.y() < 2.0 ? 1.0f : 0.0f;
    }
  }
  return map;
}

CostMapConfig WallConfig() {
  CostMapConfig config;
  config.inflation_radius_m = 0.2;
  return config;
}

// The cheapest any path can be on WallMap. Blocked: the wall's cells (|x| <= 0.1, y <= 1.9) grown
// by discs of two cells, so the squares of the cells at x in {-0.1, 0, 0.1} up to y = 2.1 (edge
// y = 2.15) block |x| <= 0.15. Every point of a segment with a finite SegmentCost lies within
// 0.025 m (half the 0.05 m sample spacing) of a free sample, so the path crosses x = 0 at
// y >= 2.125, and since every free cell costs 0 its cost is its length:
// at least 2 sqrt(3^2 + 2.125^2).
const double kLowerBound = 2.0 * std::hypot(3.0, 2.125);

// The octile distance exceeds the Euclidean one by at most sqrt(4 - 2 sqrt(2)) (at 22.5 deg), so
// no path of straight segments costs less than A*'s optimum on the 8-connected grid divided by it
// (on a map where every free cell costs the same and the ends are cell centres).
const double kOctileOverEuclidean = std::sqrt(4.0 - 2.0 * std::sqrt(2.0));

// A budget of iterations that ends the query long before the time limit: repeatable.
SamplingPlannerConfig IterationBudget(SamplingAlgorithm algorithm, std::uint32_t iterations) {
  SamplingPlannerConfig config;
  config.algorithm = algorithm;
  config.time_limit_s = 60.0;
  config.max_iterations = iterations;
  config.seed = 7;
  return config;
}

// "rrt_star" for kRrtStar, ...
std::string TestName(const ::testing::TestParamInfo<SamplingAlgorithm>& param_info) {
  std::string name = common::NameOf(param_info.param);
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

class SamplingPlannerTest : public ::testing::TestWithParam<SamplingAlgorithm> {};

TEST_P(SamplingPlannerTest, FindsAPathRoundAWallWhoseEverySegmentIsFree) {
  const SearchCostMap costs(WallMap(), WallConfig());
  const SamplingResult dut = PlanSampling(costs, IterationBudget(GetParam(), 1500), kStart, kGoal);
  ASSERT_EQ(dut.path.status, PlanStatus::kFound);
  ASSERT_GE(dut.path.points_W.size(), 3u);  // it must turn round the wall's end
  EXPECT_EQ(dut.path.points_W.front(), kStart);
  EXPECT_EQ(dut.path.points_W.back(), kGoal);
  EXPECT_EQ(dut.path.goal_W, kGoal);
  double cost = 0.0;
  for (std::size_t i = 1; i < dut.path.points_W.size(); ++i) {
    const double segment = costs.SegmentCost(dut.path.points_W[i - 1], dut.path.points_W[i]);
    EXPECT_TRUE(std::isfinite(segment)) << dut.path.points_W[i].transpose();
    cost += segment;
  }
  EXPECT_EQ(dut.path.cost, cost);
  EXPECT_GE(dut.path.cost, kLowerBound);
  EXPECT_GT(dut.path.expansions, 0);
  EXPECT_GT(dut.iterations, 0u);
  EXPECT_LE(dut.iterations, 1500u);
}

TEST_P(SamplingPlannerTest, TheSameSeedAndIterationBudgetGiveTheSamePath) {
  const SearchCostMap costs(WallMap(), WallConfig());
  const SamplingPlannerConfig config = IterationBudget(GetParam(), 1000);
  const SamplingResult first = PlanSampling(costs, config, kStart, kGoal);
  const SamplingResult second = PlanSampling(costs, config, kStart, kGoal);
  ASSERT_EQ(first.path.status, PlanStatus::kFound);
  EXPECT_EQ(second.path.points_W, first.path.points_W);
  EXPECT_EQ(second.path.cost, first.path.cost);
  EXPECT_EQ(second.path.expansions, first.path.expansions);
  EXPECT_EQ(second.iterations, first.iterations);
}

TEST_P(SamplingPlannerTest, AWalledOffGoalIsNoPathAfterTheWholeBudget) {
  common::GridLayers map = WallMap();
  const common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const double r = (g.CellCenter(ix, iy) - kGoal).norm();
      if (r > 1.0 && r < 1.3) map.Layer("traversability")(ix, iy) = 1.0f;
    }
  }
  const SamplingResult dut = PlanSampling(SearchCostMap(map, WallConfig()),
                                          IterationBudget(GetParam(), 1000), kStart, kGoal);
  EXPECT_EQ(dut.path.status, PlanStatus::kNoPath);
  EXPECT_TRUE(dut.path.points_W.empty());
  EXPECT_EQ(dut.path.cost, 0.0);
  EXPECT_EQ(dut.iterations, 1000u);
}

TEST_P(SamplingPlannerTest, ABlockedStartOrGoalIsAStatusBeforeAnyIteration) {
  const SearchCostMap costs(WallMap(), WallConfig());
  const SamplingPlannerConfig config = IterationBudget(GetParam(), 1000);
  const SamplingResult in_the_wall = PlanSampling(costs, config, {0.0, 0.0}, kGoal);
  EXPECT_EQ(in_the_wall.path.status, PlanStatus::kStartBlocked);
  EXPECT_EQ(in_the_wall.iterations, 0u);
  EXPECT_EQ(PlanSampling(costs, config, {30.0, 0.0}, kGoal).path.status, PlanStatus::kStartBlocked);
  // a blocked goal is not moved (unlike A*'s)
  const SamplingResult goal_in_the_wall = PlanSampling(costs, config, kStart, {0.05, -1.0});
  EXPECT_EQ(goal_in_the_wall.path.status, PlanStatus::kNoPath);
  EXPECT_EQ(goal_in_the_wall.iterations, 0u);
}

TEST_P(SamplingPlannerTest, WithoutAnIterationBudgetTheTimeLimitEndsTheQuery) {
  common::GridLayers map = WallMap();
  map.Layer("traversability").row(map.geometry().num_x / 2).setConstant(1.0f);  // a full wall
  SamplingPlannerConfig config;
  config.algorithm = GetParam();
  config.time_limit_s = 0.05;
  const SamplingResult dut = PlanSampling(SearchCostMap(map, WallConfig()), config, kStart, kGoal);
  EXPECT_EQ(dut.path.status, PlanStatus::kNoPath);
  EXPECT_GE(dut.planning_time_s, config.time_limit_s);
  EXPECT_GT(dut.iterations, 0u);
}

INSTANTIATE_TEST_SUITE_P(Algorithms, SamplingPlannerTest,
                         ::testing::Values(SamplingAlgorithm::kRrtStar, SamplingAlgorithm::kBitStar,
                                           SamplingAlgorithm::kRrtConnect),
                         TestName);

class AnytimePlannerTest : public ::testing::TestWithParam<SamplingAlgorithm> {};

TEST_P(AnytimePlannerTest, MoreIterationsNeverCostMoreAndNeverBeatTheBoundsFromAStar) {
  const common::GridLayers map = WallMap();
  const SearchCostMap costs(map, WallConfig());
  const GridPath astar = GridPlanner(map, WallConfig()).Plan(kStart, kGoal);
  ASSERT_EQ(astar.status, PlanStatus::kFound);
  // the geometric bound is the tighter one here
  ASSERT_LT(astar.cost / kOctileOverEuclidean, kLowerBound);
  const SamplingResult fewer = PlanSampling(costs, IterationBudget(GetParam(), 800), kStart, kGoal);
  const SamplingResult more = PlanSampling(costs, IterationBudget(GetParam(), 3000), kStart, kGoal);
  ASSERT_EQ(fewer.path.status, PlanStatus::kFound);
  ASSERT_EQ(more.path.status, PlanStatus::kFound);
  // the longer query repeats the shorter one and goes on: its best path can only improve
  EXPECT_LE(more.path.cost, fewer.path.cost);
  EXPECT_GE(more.path.cost, kLowerBound);
  EXPECT_GE(more.path.cost, astar.cost / kOctileOverEuclidean);
  EXPECT_LE(more.path.cost, 1.1 * astar.cost);
}

INSTANTIATE_TEST_SUITE_P(Algorithms, AnytimePlannerTest,
                         ::testing::Values(SamplingAlgorithm::kRrtStar,
                                           SamplingAlgorithm::kBitStar),
                         TestName);

TEST(SamplingPlannerConfigTest, RangeBoundsTheEdgesOfRrtConnect) {
  SamplingPlannerConfig config = IterationBudget(SamplingAlgorithm::kRrtConnect, 3000);
  config.range_m = 0.5;
  const SamplingResult dut =
      PlanSampling(SearchCostMap(WallMap(), WallConfig()), config, kStart, kGoal);
  ASSERT_EQ(dut.path.status, PlanStatus::kFound);
  // 6 m at least in steps of at most 0.5 m
  EXPECT_GE(dut.path.points_W.size(), 13u);
  for (std::size_t i = 1; i < dut.path.points_W.size(); ++i) {
    EXPECT_LE((dut.path.points_W[i] - dut.path.points_W[i - 1]).norm(), 0.5 + 1e-9);
  }
}

TEST(SamplingPlannerConfigTest, NamesRoundTripAndBadValuesThrowNamingThem) {
  for (const SamplingAlgorithm algorithm :
       {SamplingAlgorithm::kRrtStar, SamplingAlgorithm::kBitStar, SamplingAlgorithm::kRrtConnect}) {
    EXPECT_EQ(ParseSamplingAlgorithm(common::NameOf(algorithm)), algorithm);
  }
  EXPECT_STREQ(common::NameOf(SamplingAlgorithm::kBitStar), "bit-star");
  EXPECT_THAT([] { ParseSamplingAlgorithm("prm-star"); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("'prm-star'")));
  const SearchCostMap costs(WallMap(), WallConfig());
  SamplingPlannerConfig config;
  config.time_limit_s = 0.0;
  EXPECT_THAT([&] { (void)PlanSampling(costs, config, kStart, kGoal); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("time_limit_s")));
  config = SamplingPlannerConfig{};
  config.range_m = -1.0;
  EXPECT_THAT([&] { (void)PlanSampling(costs, config, kStart, kGoal); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("range_m must be >= 0")));
}

}  // namespace
}  // namespace trav::planner
