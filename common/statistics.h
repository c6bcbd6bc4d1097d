#pragma once

#include <vector>

namespace trav::common {

/// The q-quantile of `values` (q in [0, 1]) by the nearest-rank rule on the sorted values: the
/// element at index floor(q * (n - 1)); 0 for no values.
double Quantile(std::vector<double> values, double q);

}  // namespace trav::common
