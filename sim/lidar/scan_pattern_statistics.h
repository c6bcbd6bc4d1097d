#pragma once

#include <array>
#include <cstdint>

#include "sim/lidar/scan_pattern.h"

namespace trav::lidar {

/// How a span of a scan pattern covers the MID-360's field of view: the figures by which
/// docs/lidar.md and the tests compare a pattern with Livox's table.
struct PatternStatistics {
  static constexpr int kElevationBands = 13;  ///< 5 deg bands from [-10, -5) to [50, 55) deg
  static constexpr int kAzimuthBands = 12;    ///< 30 deg bands from [0, 30) to [330, 360) deg
  /// The field whose 1 x 1 deg cells count for the coverage: all azimuths, elevations in
  /// [-7, 52) deg (the MID-360's field of view), 360 x 59 = 21,240 cells.
  static constexpr int kFieldBottomDeg = -7;
  static constexpr int kFieldTopDeg = 52;

  std::int64_t rays{0};
  /// Share of the rays in each elevation band (rays outside every band count in none).
  std::array<double, kElevationBands> elevation_share{};
  /// Share of the rays in each azimuth band (azimuth about +z in [0, 360) deg).
  std::array<double, kAzimuthBands> azimuth_share{};
  /// Cells of the field holding at least one ray, and their fraction of the field.
  int covered_cells{0};
  double coverage{0.0};
};

/// The statistics of rays first .. first + count - 1 of `pattern` (count >= 1).
PatternStatistics ComputePatternStatistics(const ScanPattern& pattern, std::int64_t first,
                                           std::int64_t count);

/// Half the summed absolute differences of two histograms of shares: the share of rays that would
/// have to move band to turn one into the other (0 equal, 1 disjoint).
template <std::size_t N>
double TotalVariation(const std::array<double, N>& a, const std::array<double, N>& b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < N; ++k) sum += a[k] > b[k] ? a[k] - b[k] : b[k] - a[k];
  return 0.5 * sum;
}

}  // namespace trav::lidar
