#pragma once

#include <cstdint>
#include <string>

namespace trav::lidar {

/// Settings of the emulated LiDAR (defaults: Livox MID-360, reference/simulation.md section 3).
struct LidarConfig {
  bool enabled{true};
  /// Scan table in Livox's CSV format; empty: the procedural MID-360 model.
  std::string pattern_table;
  double points_per_second{200000.0};  ///< > 0
  double frame_period_s{0.1};          ///< one frame every 100 ms, > 0
  double range_min_m{0.1};             ///< blind zone: closer returns are dropped [m], >= 0
  double range_max_m{40.0};            ///< farther surfaces are not seen [m], > range_min_m
  double range_noise_m{0.02};          ///< standard deviation of the Gaussian range noise [m], >= 0
  double angular_noise_deg{
      0.1};             ///< standard deviation of the direction noise per axis [deg], >= 0
  double dropout{0.0};  ///< probability that a ray returns nothing, in [0, 1)
  /// Fraction of each frame's azimuth occluded (the paper occludes 15 % in its evaluation), in [0,
  /// 1): `occlusion_sectors` sectors of equal width at random azimuths, drawn anew per frame.
  double occlusion{0.0};
  int occlusion_sectors{3};
  std::uint64_t seed{1};  ///< noise, dropout and occlusion draws
  int threads{1};         ///< threads for casting large batches
};

/// Checks the ranges of a LiDAR config. @throws common::InputError naming the field ("lidar.<key>")
/// and value.
void ValidateLidarConfig(const LidarConfig& config);

}  // namespace trav::lidar
