#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "common/archive.h"
#include "common/pose.h"
#include "common/random.h"

namespace trav::sim {

/// The localisation error of the robot's pose estimate (scenario keys `navigation.position_noise`,
/// `yaw_noise`, `drift` and `localization_seed`): white noise with these standard deviations and a
/// drift, a random walk of the position offset growing by `drift_m_per_sqrt_s` per sqrt(s). Zero:
/// ground truth.
struct PoseNoiseConfig {
  double position_noise_m{0.0};
  double yaw_noise_rad{0.0};
  double drift_m_per_sqrt_s{0.0};
  std::uint64_t seed{1};

  /// The localisation keys of scenario section `navigation` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("position_noise", &position_noise_m, {0, 10});
    a->Field("yaw_noise", &yaw_noise_rad, {0, 3.15});
    a->Field("drift", &drift_m_per_sqrt_s, {0, 10});
    a->Field("localization_seed", &seed);
  }
};

/// Checks a config. @throws common::InputError naming the key (relative: "drift") and value.
void ValidatePoseNoiseConfig(const PoseNoiseConfig& config);

/// The pose the robot believes: the true one with the config's noise and drift. Seeded and
/// repeatable; with zero noise and drift it returns the true state unchanged.
class PoseNoise {
 public:
  explicit PoseNoise(const PoseNoiseConfig& config);

  /// The estimate of `truth` (the state at its time; call once per control step, in time order).
  common::RobotState Estimate(const common::RobotState& truth);

  /// The current drift offset [m].
  const Eigen::Vector2d& drift_W() const { return drift_W_; }

 private:
  PoseNoiseConfig config_;
  common::Random random_;
  Eigen::Vector2d drift_W_{Eigen::Vector2d::Zero()};
  double last_time_s_{0.0};
};

}  // namespace trav::sim
