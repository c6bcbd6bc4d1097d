#include "sim/lidar/scan_pattern_statistics.h"

#include <cmath>
#include <vector>

#include "common/check.h"

namespace trav::lidar {

PatternStatistics ComputePatternStatistics(const ScanPattern& pattern, std::int64_t first,
                                           std::int64_t count) {
  TRAV_DEMAND(count >= 1);
  using Stats = PatternStatistics;
  constexpr int kFieldRows = Stats::kFieldTopDeg - Stats::kFieldBottomDeg;
  std::vector<bool> covered(static_cast<std::size_t>(360 * kFieldRows), false);
  std::array<std::int64_t, Stats::kElevationBands> elevation_counts{};
  std::array<std::int64_t, Stats::kAzimuthBands> azimuth_counts{};
  constexpr double kRadToDeg = 180.0 / M_PI;
  for (std::int64_t i = first; i < first + count; ++i) {
    const Eigen::Vector3f direction = pattern.Ray(i).direction_L;
    const double elevation_deg = Elevation(direction) * kRadToDeg;
    double azimuth_deg = Azimuth(direction) * kRadToDeg;
    if (azimuth_deg < 0.0) azimuth_deg += 360.0;
    const int azimuth_cell = std::min(359, static_cast<int>(azimuth_deg));
    const int elevation_cell = static_cast<int>(std::floor(elevation_deg));
    const int band = static_cast<int>(std::floor(elevation_deg / 5.0)) + 2;  // [-10, -5) is 0
    if (band >= 0 && band < Stats::kElevationBands) ++elevation_counts[band];
    ++azimuth_counts[azimuth_cell / 30];
    if (elevation_cell >= Stats::kFieldBottomDeg && elevation_cell < Stats::kFieldTopDeg) {
      covered[static_cast<std::size_t>((elevation_cell - Stats::kFieldBottomDeg) * 360 +
                                       azimuth_cell)] = true;
    }
  }
  PatternStatistics stats;
  stats.rays = count;
  const double n = static_cast<double>(count);
  for (int k = 0; k < Stats::kElevationBands; ++k)
    stats.elevation_share[k] = elevation_counts[k] / n;
  for (int k = 0; k < Stats::kAzimuthBands; ++k) stats.azimuth_share[k] = azimuth_counts[k] / n;
  for (const bool cell : covered) stats.covered_cells += cell ? 1 : 0;
  stats.coverage = stats.covered_cells / static_cast<double>(covered.size());
  return stats;
}

}  // namespace trav::lidar
