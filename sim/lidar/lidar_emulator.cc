#include "sim/lidar/lidar_emulator.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace trav::lidar {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

}  // namespace

std::int64_t LidarEmulator::RaysBefore(double t_s) const {
  const double count = t_s * config_.points_per_second;
  const double nearest = std::round(count);
  // time stamps that are exact multiples of the ray period fall on the boundary despite rounding
  return static_cast<std::int64_t>(std::abs(count - nearest) < 1e-6 ? nearest : std::ceil(count));
}

const Eigen::Isometry3d& LidarFrame::PoseOfPoint(Eigen::Index i) const {
  const double t = points_L.stamp_s + points_L.time_offsets[i];
  // the last batch that began at or before the point's time; time offsets are floats (about 4 ns
  // of rounding at 0.1 s), so allow a microsecond, a fifth of the 5 us between rays
  const auto after = std::upper_bound(batch_times_s.begin(), batch_times_s.end(), t + 1e-6);
  const std::size_t batch = after == batch_times_s.begin()
                                ? 0
                                : static_cast<std::size_t>(after - batch_times_s.begin()) - 1;
  return batch_poses_W[batch];
}

Eigen::Matrix3Xf PointsInWorld(const LidarFrame& frame) {
  Eigen::Matrix3Xf points_W(3, frame.points_L.size());
  for (Eigen::Index i = 0; i < frame.points_L.size(); ++i) {
    points_W.col(i) =
        (frame.PoseOfPoint(i) * frame.points_L.points.col(i).cast<double>()).cast<float>();
  }
  return points_W;
}

DetectionModel::DetectionModel(const LidarConfig& config)
    : enabled_(config.detection),
      range_at_10_percent_m_(config.range_at_10_percent_m),
      exponent_(std::log(config.range_at_80_percent_m / config.range_at_10_percent_m) /
                std::log(8.0)) {
  for (int bin = 0; bin < kBins; ++bin) {
    const double reach_m =
        range_at_10_percent_m_ * std::pow(std::max(bin / double{kBins}, 1e-6) / 0.1, exponent_);
    certain_range_m_[static_cast<std::size_t>(bin)] = 0.49 * reach_m;
  }
}

double DetectionModel::Probability(double effective_reflectance, double range_m) const {
  if (!enabled_) return 1.0;
  // the reach grows with the reflectance (k >= 0): the bin's lower edge bounds it from below
  if (effective_reflectance >= 0.0 && effective_reflectance <= 1.0) {
    const int bin = std::min(kBins - 1, static_cast<int>(effective_reflectance * kBins));
    if (range_m < certain_range_m_[static_cast<std::size_t>(bin)]) return 1.0;
  }
  const double reach_m =
      range_at_10_percent_m_ * std::pow(std::max(effective_reflectance, 1e-6) / 0.1, exponent_);
  // a logistic step of width 5 % of the reach
  return 1.0 / (1.0 + std::exp((range_m - reach_m) / (0.05 * reach_m / 4.0)));
}

LidarEmulator::LidarEmulator(const LidarConfig& config)
    : config_(config), random_(config.seed), detection_(config) {
  ValidateLidarConfig(config_);
  if (!config_.pattern_table.empty()) {
    pattern_ = TablePattern::Load(config_.pattern_table);
  } else if (config_.pattern == PatternKind::kProcedural) {
    pattern_ = std::make_shared<ProceduralMid360Pattern>();
  } else {
    pattern_ = TablePattern::Mid360();
  }
  rays_per_frame_ =
      static_cast<int>(std::lround(config_.points_per_second * config_.frame_period_s));
  building_.index = -1;
}

void LidarEmulator::StartFrame(std::int64_t index, const Eigen::Isometry3d& X_WL, double t_s) {
  building_.index = index;
  building_.rays = 0;
  building_.dropped = DropCounts{};
  building_.points_L.frame_id = "L";
  building_.points_L.stamp_s =
      static_cast<double>(index * rays_per_frame_) / config_.points_per_second;
  building_.points_L.points.resize(3, rays_per_frame_);
  building_.points_L.time_offsets.resize(rays_per_frame_);
  building_.points_L.line_ids.resize(rays_per_frame_);
  building_.points_L.reflectivity.resize(rays_per_frame_);
  building_.points_L.tags.resize(rays_per_frame_);
  building_.batch_poses_W.clear();
  building_.batch_times_s.clear();
  building_.batch_poses_W.push_back(X_WL);
  building_.batch_times_s.push_back(std::max(t_s, building_.points_L.stamp_s));
  filled_ = 0;
  // occluded sectors of this frame
  occluded_sector_starts_.clear();
  if (config_.occlusion > 0.0) {
    for (int k = 0; k < config_.occlusion_sectors; ++k) {
      occluded_sector_starts_.push_back(static_cast<float>(random_.Uniform(-M_PI, M_PI)));
    }
  }
}

void LidarEmulator::FinishFrame(const Eigen::Isometry3d& X_WL) {
  building_.X_WL_end = X_WL;
  building_.points_L.points.conservativeResize(3, filled_);
  building_.points_L.time_offsets.conservativeResize(filled_);
  building_.points_L.line_ids.conservativeResize(filled_);
  building_.points_L.reflectivity.conservativeResize(filled_);
  building_.points_L.tags.conservativeResize(filled_);
  std::swap(building_, complete_);
  ready_ = true;
  building_.index = -1;
}

bool LidarEmulator::Occluded(float azimuth_rad) const {
  const float width =
      static_cast<float>(2.0 * M_PI * config_.occlusion / config_.occlusion_sectors);
  for (float start : occluded_sector_starts_) {
    float offset = std::fmod(azimuth_rad - start, static_cast<float>(2.0 * M_PI));
    if (offset < 0.0f) offset += static_cast<float>(2.0 * M_PI);
    if (offset < width) return true;
  }
  return false;
}

void LidarEmulator::TakeFrame(LidarFrame* frame) {
  TRAV_DEMAND(ready_);
  std::swap(*frame, complete_);
  ready_ = false;
}

void LidarEmulator::Scan(const RayScene& scene, double t_begin_s, double t_end_s,
                         const Eigen::Isometry3d& X_WL) {
  const std::int64_t end_ray = RaysBefore(t_end_s);
  const Eigen::Matrix3f R_WL = X_WL.linear().cast<float>();
  const Eigen::Vector3f p_WL = X_WL.translation().cast<float>();
  const float angular_sigma = static_cast<float>(config_.angular_noise_deg * kDegToRad);

  while (next_ray_ < end_ray) {
    // rays of one frame at a time
    const std::int64_t frame = next_ray_ / rays_per_frame_;
    if (building_.index != frame) {
      StartFrame(frame, X_WL, t_begin_s);
    } else if (building_.batch_times_s.back() < t_begin_s) {
      building_.batch_poses_W.push_back(X_WL);
      building_.batch_times_s.push_back(t_begin_s);
    }
    const std::int64_t chunk_end = std::min(end_ray, (frame + 1) * rays_per_frame_);
    const auto count = static_cast<Eigen::Index>(chunk_end - next_ray_);
    if (directions_L_.cols() < count) {
      pattern_directions_L_.resize(3, count);
      pattern_lines_.resize(count);
      directions_L_.resize(3, count);
      directions_W_.resize(3, count);
      lines_.resize(count);
      times_.resize(count);
    }

    // the rays that are fired: occlusion and dropout first, then direction noise
    pattern_->Rays(next_ray_, count, &pattern_directions_L_, &pattern_lines_);
    Eigen::Index kept = 0;
    for (std::int64_t i = next_ray_; i < chunk_end; ++i) {
      const auto k = static_cast<Eigen::Index>(i - next_ray_);
      ++building_.rays;
      if (!occluded_sector_starts_.empty() && Occluded(Azimuth(pattern_directions_L_.col(k)))) {
        ++building_.dropped.occluded;
        continue;
      }
      if (config_.dropout > 0.0 && random_.Bernoulli(config_.dropout)) {
        ++building_.dropped.dropout;
        continue;
      }
      Eigen::Vector3f direction = pattern_directions_L_.col(k);
      if (angular_sigma > 0.0f) {
        const Eigen::Vector3f e1 = direction.unitOrthogonal();
        const Eigen::Vector3f e2 = direction.cross(e1);
        direction = (direction + angular_sigma * (static_cast<float>(random_.Normal()) * e1 +
                                                  static_cast<float>(random_.Normal()) * e2))
                        .normalized();
      }
      directions_L_.col(kept) = direction;
      lines_[kept] = pattern_lines_[k];
      times_[kept] = static_cast<float>(static_cast<double>(i - frame * rays_per_frame_) /
                                        config_.points_per_second);
      ++kept;
    }
    directions_W_.leftCols(kept).noalias() = R_WL * directions_L_.leftCols(kept);
    scene.Cast(p_WL, directions_W_.leftCols(kept), static_cast<float>(config_.range_max_m), &hits_,
               config_.threads);

    // returns within range that are strong enough become points in L, with range noise and
    // their reflectivity: diffuse reflectance times cos(incidence) (no lower than the rough-surface
    // floor) on Livox's 0..150 scale
    for (Eigen::Index k = 0; k < kept; ++k) {
      const float range = hits_.range_m[k];
      if (!std::isfinite(range)) {
        ++building_.dropped.miss;
        continue;
      }
      if (range < config_.range_min_m) {
        ++building_.dropped.blind;
        continue;
      }
      const double cos_incidence =
          std::max(config_.incidence_floor,
                   std::abs(static_cast<double>(hits_.normal_W.col(k).dot(directions_W_.col(k)))));
      const double effective =
          static_cast<double>(scene.reflectance(hits_.object_id[k])) * cos_incidence;
      const double p_return = detection_.Probability(effective, range);
      if (p_return < 1.0 && random_.Uniform() >= p_return) {
        ++building_.dropped.weak;
        continue;
      }
      const float noisy = range + static_cast<float>(config_.range_noise_m * random_.Normal());
      const double reflectivity =
          150.0 * effective * (1.0 + config_.reflectivity_noise * random_.Normal());
      building_.points_L.points.col(filled_) = noisy * directions_L_.col(k);
      building_.points_L.time_offsets[filled_] = times_[k];
      building_.points_L.line_ids[filled_] = lines_[k];
      building_.points_L.reflectivity[filled_] =
          static_cast<std::uint8_t>(std::lround(std::clamp(reflectivity, 0.0, 150.0)));
      building_.points_L.tags[filled_] = 0;
      ++filled_;
    }
    next_ray_ = chunk_end;
    if (next_ray_ == (frame + 1) * rays_per_frame_) FinishFrame(X_WL);
  }
}

}  // namespace trav::lidar
