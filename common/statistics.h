#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace trav::common {

/// The q-quantile of `values` (q in [0, 1]) by the nearest-rank rule on the sorted values: the
/// element at index floor(q * (n - 1)); 0 for no values.
double Quantile(std::vector<double> values, double q);

/// The ranks of `values` (1 for the smallest), tied values sharing their average rank.
std::vector<double> AverageRanks(const std::vector<double>& values);

/// Area under the ROC curve of `scores` for the cells labelled `positive` (same length): the
/// probability that a random positive scores higher than a random negative, a tie counting half
/// (the Mann-Whitney U over P N). NaN when either class is empty.
double Auroc(const std::vector<double>& scores, const std::vector<bool>& positive);

/// Average precision of `scores` for the positives: the sum over the distinct scores, from the
/// highest, of (recall gained) x (precision at that score), tied scores taken as one threshold
/// (scikit-learn's average_precision_score). NaN without positives.
double AveragePrecision(const std::vector<double>& scores, const std::vector<bool>& positive);

/// Spearman's rank correlation: the Pearson correlation of the average ranks. NaN for fewer than
/// two pairs or a side without spread.
double Spearman(const std::vector<double>& x, const std::vector<double>& y);

/// A non-decreasing step function fitted to weighted points (x_i, y_i) by least squares (the pool
/// adjacent violators algorithm): the calibration that maps a score to the mean truth of the
/// scores around it, whatever the score's own scale.
class IsotonicFit {
 public:
  /// Points with weights > 0 (all three the same length); x need not be sorted.
  IsotonicFit(const std::vector<double>& x, const std::vector<double>& y,
              const std::vector<double>& weights);

  /// The fitted value at `x`: that of the block holding the largest fitted x not above it (the
  /// first block below every x); NaN if the fit has no points.
  double operator()(double x) const;

 private:
  std::vector<double> block_start_x_;  // the smallest x of each block, increasing
  std::vector<double> block_value_;    // the weighted mean of y over each block, non-decreasing
};

/// The percentile bootstrap interval of the mean of `values` at `level` (0.95: the 2.5 % and
/// 97.5 % quantiles of `resamples` means of resamples drawn with replacement, seeded by `seed`).
/// Both NaN for no values.
std::pair<double, double> BootstrapMeanInterval(const std::vector<double>& values, double level,
                                                int resamples, std::uint64_t seed);

}  // namespace trav::common
