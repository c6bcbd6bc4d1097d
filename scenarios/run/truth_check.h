#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/enum_names.h"
#include "controller/skid_steer.h"
#include "mapping/ground_truth.h"
#include "mapping/physical_truth.h"
#include "scenarios/run/output_folder.h"
#include "sim/terrain.h"

namespace trav::scenarios {

/// What the robot did when driven straight ahead from a sample pose in MuJoCo.
enum class DriveResult {
  kCrossed,  ///< covered the distance with only its wheels touching the world
  kStuck,    ///< did not cover it in the time allowed (slipped, stalled, or a wheel blocked)
  kTipped,   ///< its base tilted more than kTippedTilt_deg from upright
  kScraped,  ///< its chassis touched the ground or an obstacle
  /// it hit an obstacle's face (sim::IsCollision: a wheel against a trunk or a wall)
  kCollided,
};

/// The names of DriveResult's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<DriveResult>, 5> kDriveResultNames{
    {{DriveResult::kCrossed, "crossed"},
     {DriveResult::kStuck, "stuck"},
     {DriveResult::kTipped, "tipped"},
     {DriveResult::kScraped, "scraped"},
     {DriveResult::kCollided, "collided"}}};
constexpr const auto& EnumNames(DriveResult) { return kDriveResultNames; }

/// Tilt from upright beyond which a drive counts as tipped over [deg]: on a 45 deg slope the robot
/// rolls over across it and rears without climbing up it (docs/navigation.md).
constexpr double kTippedTilt_deg = 45.0;

/// One (pose, heading) sample of the physical truth's check.
struct TruthCheckSample {
  double x_m{0.0}, y_m{0.0}, yaw_rad{0.0};  ///< the start pose in W
  /// The physical truth along the drive: the highest cost of the poses every 0.05 m from the start
  /// to `drive_m` ahead, and whether all of them are traversable.
  double predicted_cost{0.0};
  bool predicted_traversable{true};
  mapping::RestingLimit limit{mapping::RestingLimit::kPitch};  ///< of the costliest pose
  DriveResult result{DriveResult::kCrossed};
  double moved_m{0.0};       ///< distance covered along the start heading [m]
  double max_tilt_deg{0.0};  ///< largest tilt of the base from upright during the drive [deg]
  /// The truth agrees with the robot: traversable and crossed, or untraversable and not crossed.
  bool Agrees() const { return predicted_traversable == (result == DriveResult::kCrossed); }
};

/// The check's settings.
struct TruthCheckOptions {
  /// The world: its type, seed and parameters; its size and resolution are the check's (a square
  /// of `world_size_m`, the height field at 0.1 m, 0.05 m indoors as in the evaluation).
  sim::TerrainConfig terrain{};
  int samples{300};          ///< half predicted traversable, half not, where the world has them
  double world_size_m{20};   ///< side of the square world [m]
  double drive_m{1.0};       ///< distance driven straight ahead [m]
  double speed_m_s{1.0};     ///< commanded speed (the limits were measured at 1 m/s) [m/s]
  double time_limit_s{4.0};  ///< time allowed for the distance [s]
};

/// Validates the physical ground truth (mapping::ComputePhysicalTruth) against the simulator on
/// one seeded world (`options.terrain`, its seed): draws start poses and headings (seeded), the
/// robot resting there with no obstacle within its circumscribed radius, half of them with a drive
/// the truth calls traversable and half with one it does not (as many as `samples` x 200 draws
/// find); then places the Scout Mini of `robot_model_path` there in MuJoCo, lets it settle for 0.5
/// s and commands `speed_m_s` straight ahead until it covers `drive_m`, tips, or the time runs out.
/// Deterministic for a seed.
std::vector<TruthCheckSample> CheckPhysicalTruth(const TruthCheckOptions& options,
                                                 const std::string& robot_model_path,
                                                 const controller::SkidSteerConfig& skid_steer,
                                                 const mapping::GroundTruthConfig& truth);

/// Per terrain type: samples, agreement and the confusion counts.
struct TruthCheckSummary {
  std::string terrain;
  int samples{0};
  int predicted_traversable{0};
  int agree_traversable{0};    ///< predicted traversable and crossed
  int agree_untraversable{0};  ///< predicted untraversable and not crossed
  double Agreement() const {
    return samples > 0 ? static_cast<double>(agree_traversable + agree_untraversable) / samples
                       : 0.0;
  }
};

TruthCheckSummary Summarize(const std::string& terrain,
                            const std::vector<TruthCheckSample>& samples);

/// Writes truth_check.csv (one row per sample with its terrain type) and truth_check.json (the
/// summaries and the options) into `folder`.
void WriteTruthCheck(const std::vector<std::pair<std::string, std::vector<TruthCheckSample>>>& runs,
                     const TruthCheckOptions& options, const OutputFolder& folder);

}  // namespace trav::scenarios
