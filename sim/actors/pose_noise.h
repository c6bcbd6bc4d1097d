#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include <Eigen/Geometry>

#include "common/archive.h"
#include "common/enum_names.h"
#include "common/pose.h"
#include "common/random.h"

namespace trav::sim {

/// Where the stack's pose comes from (scenario key `localization.method`).
enum class LocalizationMethod {
  kTrue,          ///< the true pose (with the `navigation` noise keys, when set)
  kDriftModel,    ///< LiDAR-inertial odometry's error: drift growing with the distance driven
  kScanMatching,  ///< a LiDAR odometry on the scans (mapping::LidarOdometry), not this model
};

/// The names of LocalizationMethod's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<LocalizationMethod>, 3> kLocalizationMethodNames{
    {{LocalizationMethod::kTrue, "true"},
     {LocalizationMethod::kDriftModel, "drift-model"},
     {LocalizationMethod::kScanMatching, "scan-matching"}}};
constexpr const auto& EnumNames(LocalizationMethod) { return kLocalizationMethodNames; }

/// The odometry drift of `localization.method: drift-model`: each stretch ds [m] the robot drives
/// adds independent errors to the estimate's yaw, horizontal position and height, of standard
/// deviation rate * sqrt(ds). Position increments are rotated by the yaw error, so a heading
/// error turns into position error over the distance that follows, as in real odometry. Roll and
/// pitch do not drift (the IMU's gravity keeps them observable). Defaults: the KITTI odometry
/// benchmark's LOAM figures (0.55 % of the distance in translation, 0.0013 deg/m in rotation over
/// 100 to 800 m segments) written as random walks that reach them at 100 m: 0.055 m/sqrt(m) and
/// 0.013 deg/sqrt(m); FAST-LIO2, the paper's odometry, is more accurate than LOAM on the
/// benchmarks of its paper, so these bound its drift from above (docs/localization.md).
struct OdometryDriftConfig {
  double translation_m_per_sqrt_m{0.055};  ///< per horizontal axis
  double z_m_per_sqrt_m{0.055};
  double yaw_rad_per_sqrt_m{2.27e-4};

  /// The keys of scenario section `localization` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("translation_drift", &translation_m_per_sqrt_m, {0, 10});
    a->Field("z_drift", &z_m_per_sqrt_m, {0, 10});
    a->Field("yaw_drift", &yaw_rad_per_sqrt_m, {0, 1});
  }
};

/// The localisation error of the pose the stack believes: white noise with the `navigation` keys'
/// standard deviations, a random walk of the position offset growing by `drift_m_per_sqrt_s` per
/// sqrt(s), and with `method` drift-model the odometry drift. All zero and method `true`: the
/// ground truth.
struct PoseNoiseConfig {
  double position_noise_m{0.0};
  double yaw_noise_rad{0.0};
  double drift_m_per_sqrt_s{0.0};
  std::uint64_t seed{1};
  LocalizationMethod method{LocalizationMethod::kTrue};
  OdometryDriftConfig odometry{};

  /// The localisation keys of scenario section `navigation` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("position_noise", &position_noise_m, {0, 10});
    a->Field("yaw_noise", &yaw_noise_rad, {0, 3.15});
    a->Field("drift", &drift_m_per_sqrt_s, {0, 10});
    a->Field("localization_seed", &seed);
  }

  /// Whether the estimate can differ from the truth.
  bool active() const {
    return position_noise_m > 0.0 || yaw_noise_rad > 0.0 || drift_m_per_sqrt_s > 0.0 ||
           method != LocalizationMethod::kTrue;
  }
};

/// Checks the `navigation` keys of a config (the odometry's: ValidateOdometryDriftConfig).
/// @throws common::InputError naming the key (relative: "drift") and value.
void ValidatePoseNoiseConfig(const PoseNoiseConfig& config);

/// Checks a drift config. @throws common::InputError naming the key (relative: "yaw_drift") and
/// value.
void ValidateOdometryDriftConfig(const OdometryDriftConfig& config);

/// The pose the robot believes: the true one with the config's noise and drift. Seeded and
/// repeatable; when the config is not active() it returns the true state unchanged. Method
/// scan-matching is not a model: its estimate comes from mapping::LidarOdometry, and here only the
/// `navigation` noise keys act.
class PoseNoise {
 public:
  explicit PoseNoise(const PoseNoiseConfig& config);

  /// The estimate of `truth` (the state at its time; call once per control step, in time order).
  common::RobotState Estimate(const common::RobotState& truth);

  /// The current time-driven drift offset [m].
  const Eigen::Vector2d& drift_W() const { return drift_W_; }

  /// The odometry drift so far: the position error [m] and the yaw error [rad].
  const Eigen::Vector3d& odometry_position_error_W() const { return odometry_position_error_W_; }
  double odometry_yaw_error_rad() const { return odometry_yaw_error_rad_; }

 private:
  // Adds the odometry drift of the stretch from the previous true position to `p_W`.
  void DriftAlong(const Eigen::Vector3d& p_W);

  PoseNoiseConfig config_;
  common::Random random_;
  Eigen::Vector2d drift_W_{Eigen::Vector2d::Zero()};
  double last_time_s_{0.0};
  std::optional<Eigen::Vector3d> last_p_W_;
  Eigen::Vector3d odometry_position_error_W_{Eigen::Vector3d::Zero()};
  double odometry_yaw_error_rad_{0.0};
};

}  // namespace trav::sim
