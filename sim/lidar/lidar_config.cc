#include "sim/lidar/lidar_config.h"

#include "common/input_error.h"

namespace trav::lidar {
void ValidateLidarConfig(const LidarConfig& c) {
  common::RequireValue(c.points_per_second > 0.0, "rate", c.points_per_second, "must be > 0");
  common::RequireValue(c.frame_period_s > 0.0, "frame_period", c.frame_period_s, "must be > 0");
  common::RequireValue(c.points_per_second * c.frame_period_s >= 1.0, "frame_period",
                       c.frame_period_s, "must hold at least one point at the configured rate");
  common::RequireValue(c.range_min_m >= 0.0, "range_min", c.range_min_m, "must be >= 0");
  common::RequireValue(c.range_max_m > c.range_min_m, "range_max", c.range_max_m,
                       "must be > range_min");
  common::RequireValue(c.range_at_10_percent_m > 0.0, "range_at_10_percent",
                       c.range_at_10_percent_m, "must be > 0");
  common::RequireValue(c.range_at_80_percent_m >= c.range_at_10_percent_m, "range_at_80_percent",
                       c.range_at_80_percent_m, "must be >= range_at_10_percent");
  common::RequireValue(c.incidence_floor >= 0.0 && c.incidence_floor <= 1.0, "incidence_floor",
                       c.incidence_floor, "must be in [0, 1]");
  common::RequireValue(c.reflectivity_noise >= 0.0, "reflectivity_noise", c.reflectivity_noise,
                       "must be >= 0");
  common::RequireValue(c.range_noise_m >= 0.0, "range_noise", c.range_noise_m, "must be >= 0");
  common::RequireValue(c.angular_noise_deg >= 0.0, "angular_noise_deg", c.angular_noise_deg,
                       "must be >= 0");
  common::RequireValue(c.dropout >= 0.0 && c.dropout < 1.0, "dropout", c.dropout,
                       "must be in [0, 1)");
  common::RequireValue(c.occlusion >= 0.0 && c.occlusion < 1.0, "occlusion", c.occlusion,
                       "must be in [0, 1)");
  common::RequireValue(c.occlusion_sectors >= 1, "occlusion_sectors", c.occlusion_sectors,
                       "must be >= 1");
  common::RequireValue(c.threads >= 1 && c.threads <= 64, "threads", c.threads,
                       "must be in [1, 64]");
}

}  // namespace trav::lidar
