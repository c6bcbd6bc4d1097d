#include "common/statistics.h"

#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace trav::common {
namespace {

using ::testing::ElementsAre;

TEST(StatisticsTest, TiedValuesShareTheirAverageRank) {
  EXPECT_THAT(AverageRanks({3.0, 1.0, 3.0, 2.0}), ElementsAre(3.5, 1.0, 3.5, 2.0));
  EXPECT_THAT(AverageRanks({5.0, 5.0, 5.0}), ElementsAre(2.0, 2.0, 2.0));
}

TEST(StatisticsTest, AurocCountsThePositiveNegativePairsInOrderWithTiesAsHalf) {
  // pairs (positive, negative): 0.9 > 0.8, 0.9 > 0.1, 0.3 < 0.8, 0.3 > 0.1
  EXPECT_DOUBLE_EQ(Auroc({0.9, 0.8, 0.3, 0.1}, {true, false, true, false}), 0.75);
  EXPECT_DOUBLE_EQ(Auroc({0.9, 0.8, 0.3, 0.1}, {true, true, false, false}), 1.0);
  EXPECT_DOUBLE_EQ(Auroc({0.1, 0.8, 0.3, 0.9}, {true, true, false, false}), 0.25);
  // a constant map cannot rank: every pair ties
  EXPECT_DOUBLE_EQ(Auroc({0.2, 0.2, 0.2, 0.2, 0.2}, {true, false, false, true, false}), 0.5);
  EXPECT_TRUE(std::isnan(Auroc({0.2, 0.4}, {false, false})));
  EXPECT_TRUE(std::isnan(Auroc({0.2, 0.4}, {true, true})));
}

TEST(StatisticsTest, AveragePrecisionWeighsThePrecisionAtEachRecalledPositive) {
  // 0.9 (positive): precision 1; 0.8 negative; 0.3 (positive): precision 2/3
  EXPECT_DOUBLE_EQ(AveragePrecision({0.9, 0.8, 0.3, 0.1}, {true, false, true, false}),
                   (1.0 + 2.0 / 3.0) / 2.0);
  EXPECT_DOUBLE_EQ(AveragePrecision({0.9, 0.8, 0.3, 0.1}, {true, true, false, false}), 1.0);
  // tied scores are one threshold: a constant map's precision is the share of positives
  EXPECT_DOUBLE_EQ(AveragePrecision({0.5, 0.5, 0.5, 0.5}, {false, true, false, false}), 0.25);
  EXPECT_TRUE(std::isnan(AveragePrecision({0.5, 0.1}, {false, false})));
}

TEST(StatisticsTest, SpearmanIsThePearsonCorrelationOfTheRanks) {
  EXPECT_DOUBLE_EQ(Spearman({1, 2, 3, 4}, {10, 200, 300, 4000}), 1.0);
  EXPECT_DOUBLE_EQ(Spearman({1, 2, 3, 4}, {4, 3, 2, 1}), -1.0);
  EXPECT_DOUBLE_EQ(Spearman({1, 2, 3}, {1, 3, 2}), 0.5);
  EXPECT_TRUE(std::isnan(Spearman({1, 2, 3}, {7, 7, 7})));
  EXPECT_TRUE(std::isnan(Spearman({1}, {2})));
}

TEST(StatisticsTest, IsotonicFitPoolsAdjacentViolatorsByWeight) {
  const IsotonicFit fit({4, 1, 3, 2}, {4, 1, 2, 3}, {1, 1, 1, 1});
  EXPECT_DOUBLE_EQ(fit(1.0), 1.0);
  EXPECT_DOUBLE_EQ(fit(2.0), 2.5);  // 3 then 2 pooled
  EXPECT_DOUBLE_EQ(fit(3.5), 2.5);
  EXPECT_DOUBLE_EQ(fit(4.0), 4.0);
  EXPECT_DOUBLE_EQ(fit(0.0), 1.0);  // below every x: the first block
  EXPECT_DOUBLE_EQ(fit(9.0), 4.0);
  const IsotonicFit weighted({1, 2}, {3, 2}, {1, 3});
  EXPECT_DOUBLE_EQ(weighted(1.0), (3.0 + 3.0 * 2.0) / 4.0);
  EXPECT_TRUE(std::isnan(IsotonicFit({}, {}, {})(0.5)));
}

TEST(StatisticsTest, BootstrapIntervalIsSeededAndHoldsTheMean) {
  const auto [low, high] = BootstrapMeanInterval({2.0, 2.0, 2.0}, 0.95, 200, 1);
  EXPECT_EQ(low, 2.0);
  EXPECT_EQ(high, 2.0);
  const std::vector<double> values{-1.0, 0.5, 2.0, 3.5, 1.0, 0.0, 2.5, 1.5};  // mean 1.25
  const auto interval = BootstrapMeanInterval(values, 0.95, 2000, 7);
  EXPECT_EQ(interval, BootstrapMeanInterval(values, 0.95, 2000, 7));
  EXPECT_LT(interval.first, 1.25);
  EXPECT_GT(interval.second, 1.25);
  EXPECT_GT(interval.first, -1.0);
  EXPECT_LT(interval.second, 3.5);
  const auto wider = BootstrapMeanInterval(values, 0.99, 2000, 7);
  EXPECT_LE(wider.first, interval.first);
  EXPECT_GE(wider.second, interval.second);
  EXPECT_TRUE(std::isnan(BootstrapMeanInterval({}, 0.95, 10, 1).first));
}

}  // namespace
}  // namespace trav::common
