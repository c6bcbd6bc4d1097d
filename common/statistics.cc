#include "common/statistics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>

#include "common/random.h"

namespace trav::common {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The indices of `values` ordered by value, highest first.
std::vector<std::size_t> OrderDescending(const std::vector<double>& values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return values[a] > values[b]; });
  return order;
}

}  // namespace

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

std::vector<double> AverageRanks(const std::vector<double>& values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(values.size());
  for (std::size_t first = 0; first < order.size();) {
    std::size_t last = first;
    while (last + 1 < order.size() && values[order[last + 1]] == values[order[first]]) ++last;
    // positions first..last (0-based) share the rank of their middle, 1-based
    const double rank = 0.5 * static_cast<double>(first + last) + 1.0;
    for (std::size_t i = first; i <= last; ++i) ranks[order[i]] = rank;
    first = last + 1;
  }
  return ranks;
}

double Auroc(const std::vector<double>& scores, const std::vector<bool>& positive) {
  const std::vector<double> ranks = AverageRanks(scores);
  double positives = 0.0, rank_sum = 0.0;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    if (!positive[i]) continue;
    positives += 1.0;
    rank_sum += ranks[i];
  }
  const double negatives = static_cast<double>(scores.size()) - positives;
  if (positives == 0.0 || negatives == 0.0) return kNaN;
  return (rank_sum - positives * (positives + 1.0) / 2.0) / (positives * negatives);
}

double AveragePrecision(const std::vector<double>& scores, const std::vector<bool>& positive) {
  const double positives = static_cast<double>(std::count(positive.begin(), positive.end(), true));
  if (positives == 0.0) return kNaN;
  const std::vector<std::size_t> order = OrderDescending(scores);
  double precision_sum = 0.0, true_positives = 0.0;
  for (std::size_t first = 0; first < order.size();) {
    std::size_t last = first;
    double gained = positive[order[first]] ? 1.0 : 0.0;
    while (last + 1 < order.size() && scores[order[last + 1]] == scores[order[first]]) {
      ++last;
      gained += positive[order[last]] ? 1.0 : 0.0;
    }
    true_positives += gained;
    precision_sum += gained * true_positives / static_cast<double>(last + 1);
    first = last + 1;
  }
  return precision_sum / positives;
}

double Spearman(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  if (n < 2) return kNaN;
  const std::vector<double> rx = AverageRanks(x), ry = AverageRanks(y);
  const double mean = 0.5 * static_cast<double>(n + 1);  // of ranks 1..n, ties included
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxy += (rx[i] - mean) * (ry[i] - mean);
    sxx += (rx[i] - mean) * (rx[i] - mean);
    syy += (ry[i] - mean) * (ry[i] - mean);
  }
  if (sxx == 0.0 || syy == 0.0) return kNaN;
  return sxy / std::sqrt(sxx * syy);
}

IsotonicFit::IsotonicFit(const std::vector<double>& x, const std::vector<double>& y,
                         const std::vector<double>& weights) {
  std::vector<std::size_t> order(x.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return x[a] < x[b]; });
  // pool adjacent violators: each block holds its weighted sum and weight
  std::vector<double> sum, weight;
  for (const std::size_t i : order) {
    block_start_x_.push_back(x[i]);
    sum.push_back(weights[i] * y[i]);
    weight.push_back(weights[i]);
    while (sum.size() > 1 &&
           sum[sum.size() - 2] / weight[weight.size() - 2] >= sum.back() / weight.back()) {
      sum[sum.size() - 2] += sum.back();
      weight[weight.size() - 2] += weight.back();
      sum.pop_back();
      weight.pop_back();
      block_start_x_.pop_back();
    }
  }
  for (std::size_t b = 0; b < sum.size(); ++b) block_value_.push_back(sum[b] / weight[b]);
}

double IsotonicFit::operator()(double x) const {
  if (block_value_.empty()) return kNaN;
  const auto after = std::upper_bound(block_start_x_.begin(), block_start_x_.end(), x);
  const auto block = after == block_start_x_.begin() ? 0 : after - block_start_x_.begin() - 1;
  return block_value_[static_cast<std::size_t>(block)];
}

std::pair<double, double> BootstrapMeanInterval(const std::vector<double>& values, double level,
                                                int resamples, std::uint64_t seed) {
  if (values.empty()) return {kNaN, kNaN};
  Random random(seed);
  std::vector<double> means(static_cast<std::size_t>(resamples));
  for (double& mean : means) {
    double sum = 0.0;
    for (std::size_t i = 0; i < values.size(); ++i)
      sum += values[random.UniformIndex(values.size())];
    mean = sum / static_cast<double>(values.size());
  }
  const double tail = 0.5 * (1.0 - level);
  return {Quantile(means, tail), Quantile(means, 1.0 - tail)};
}

}  // namespace trav::common
