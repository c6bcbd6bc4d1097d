#include "scenarios/run/truth_check.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/footprint.h"
#include "common/random.h"
#include "scenarios/run/scenario_run.h"
#include "sim/simulation.h"
#include "sim/terrain_geometry.h"

namespace trav::scenarios {
namespace {

constexpr double kPoseSpacing_m = 0.05;  // the truth's poses along a drive
constexpr double kSettle_s = 0.5;
constexpr int kDrawsPerSample = 200;
constexpr double kRadToDeg = 180.0 / M_PI;
// Keep-out from the world's edge for start poses [m]: the drive and the robot stay on the world.
constexpr double kEdgeMargin_m = 2.0;

// True if no obstacle stands within `radius_m` of p_W on the obstacle grid (the robot can be
// placed there: the simulation rests it on the ground alone).
bool ClearOfObstacles(const common::GridGeometry& g, const Eigen::MatrixXf& obstacle_top_m,
                      const Eigen::Vector2d& p_W, double radius_m) {
  return g.CellIndex(p_W).has_value() &&
         !common::AnyCellWithin(
             g, p_W, radius_m, [&](int ix, int iy) { return !std::isnan(obstacle_top_m(ix, iy)); });
}

// The truth along a straight drive: the highest cost of its poses and whether all are
// traversable; false if a pose is off the world.
bool PredictDrive(const mapping::RestingSurface& surface, const mapping::GroundTruthConfig& truth,
                  double drive_m, TruthCheckSample* sample) {
  const Eigen::Vector2d start(sample->x_m, sample->y_m);
  const Eigen::Vector2d heading(std::cos(sample->yaw_rad), std::sin(sample->yaw_rad));
  const int poses = static_cast<int>(std::lround(drive_m / kPoseSpacing_m));
  sample->predicted_cost = 0.0;
  sample->predicted_traversable = true;
  for (int i = 0; i <= poses; ++i) {
    const mapping::PoseAssessment pose =
        mapping::AssessPose(surface, start + i * kPoseSpacing_m * heading, sample->yaw_rad,
                            mapping::RestingBody{}, truth);
    if (!pose.known) return false;
    if (i == 0 || pose.cost > sample->predicted_cost) {
      sample->predicted_cost = pose.cost;
      sample->limit = pose.limit;
    }
    sample->predicted_traversable = sample->predicted_traversable && pose.traversable;
  }
  return true;
}

// Drives the robot from the sample's pose in MuJoCo and records what it did.
void Drive(const sim::TerrainWorld& world, const TruthCheckOptions& options,
           const sim::WorldOptions& world_options, const controller::SkidSteerConfig& skid_steer,
           TruthCheckSample* sample) {
  common::Pose2 start;
  start.position = Eigen::Vector2d(sample->x_m, sample->y_m);
  start.yaw = sample->yaw_rad;
  sim::Simulation simulation(world, start, world_options);
  const int settle_steps = static_cast<int>(std::lround(kSettle_s / simulation.timestep()));
  for (int i = 0; i < settle_steps; ++i) simulation.Step();
  const Eigen::Vector2d origin = simulation.State().X_WB.translation().head<2>();
  const Eigen::Vector2d heading(std::cos(sample->yaw_rad), std::sin(sample->yaw_rad));
  simulation.SetWheelSpeedCommands(controller::ToWheelSpeeds({options.speed_m_s, 0.0}, skid_steer));
  const int drive_steps =
      static_cast<int>(std::lround(options.time_limit_s / simulation.timestep()));
  std::vector<sim::RobotContact> contacts;
  bool scraped = false;
  bool collided = false;
  bool tipped = false;
  for (int i = 0; i < drive_steps; ++i) {
    if (simulation.Step() == sim::StepStatus::kDiverged) break;
    simulation.RobotContacts(&contacts);
    for (const sim::RobotContact& contact : contacts) {
      if (sim::IsCollision(contact)) {
        collided = true;
      } else if (contact.part == sim::RobotPart::kBody) {
        scraped = true;
      }
    }
    const Eigen::Isometry3d X_WB = simulation.State().X_WB;
    const double tilt_deg = std::acos(std::clamp(X_WB.linear()(2, 2), -1.0, 1.0)) * kRadToDeg;
    sample->max_tilt_deg = std::max(sample->max_tilt_deg, tilt_deg);
    sample->moved_m = (X_WB.translation().head<2>() - origin).dot(heading);
    if (tilt_deg > kTippedTilt_deg) {
      tipped = true;
      break;
    }
    if (sample->moved_m >= options.drive_m) break;
  }
  if (tipped) {
    sample->result = DriveResult::kTipped;
  } else if (collided) {
    sample->result = DriveResult::kCollided;
  } else if (scraped) {
    sample->result = DriveResult::kScraped;
  } else if (sample->moved_m >= options.drive_m) {
    sample->result = DriveResult::kCrossed;
  } else {
    sample->result = DriveResult::kStuck;
  }
}

}  // namespace

std::vector<TruthCheckSample> CheckPhysicalTruth(const TruthCheckOptions& options,
                                                 const std::string& robot_model_path,
                                                 const controller::SkidSteerConfig& skid_steer,
                                                 const mapping::GroundTruthConfig& truth) {
  sim::TerrainConfig terrain = options.terrain;
  terrain.size_m = Eigen::Vector2d::Constant(options.world_size_m);
  // indoor walls are thin: the evaluation's finer height field
  terrain.resolution_m = terrain.type == sim::TerrainType::kIndoor ? 0.05 : 0.1;
  const sim::TerrainWorld world = sim::GenerateTerrain(terrain);
  const sim::ObstacleRaster obstacles = RestingObstacles(world);
  const mapping::RestingSurface surface{world.geometry, world.height_m, obstacles.geometry,
                                        obstacles.top_m};
  const double keep_out_m = common::Footprint{}.CircumscribedRadius() + 0.05;

  // seeded draws, half of the samples predicted traversable and half not
  common::Random random(terrain.seed);
  const int wanted_each = options.samples / 2;
  std::vector<TruthCheckSample> traversable, untraversable;
  const double half = 0.5 * options.world_size_m - kEdgeMargin_m;
  for (int draw = 0; draw < kDrawsPerSample * options.samples; ++draw) {
    if (static_cast<int>(traversable.size()) >= options.samples - wanted_each &&
        static_cast<int>(untraversable.size()) >= wanted_each)
      break;
    TruthCheckSample sample;
    sample.x_m = random.Uniform(-half, half);
    sample.y_m = random.Uniform(-half, half);
    sample.yaw_rad = random.Uniform(-M_PI, M_PI);
    const Eigen::Vector2d start(sample.x_m, sample.y_m);
    if (!ClearOfObstacles(obstacles.geometry, obstacles.top_m, start, keep_out_m)) continue;
    const mapping::PoseAssessment rest =
        mapping::AssessPose(surface, start, sample.yaw_rad, mapping::RestingBody{}, truth);
    if (!rest.known || !rest.traversable) continue;
    if (!PredictDrive(surface, truth, options.drive_m, &sample)) continue;
    std::vector<TruthCheckSample>& stratum =
        sample.predicted_traversable ? traversable : untraversable;
    const int wanted = sample.predicted_traversable ? options.samples - wanted_each : wanted_each;
    if (static_cast<int>(stratum.size()) < wanted) stratum.push_back(sample);
  }
  std::vector<TruthCheckSample> samples = std::move(traversable);
  samples.insert(samples.end(), untraversable.begin(), untraversable.end());

  sim::WorldOptions world_options;
  world_options.robot_model_path = robot_model_path;
  for (TruthCheckSample& sample : samples)
    Drive(world, options, world_options, skid_steer, &sample);
  return samples;
}

TruthCheckSummary Summarize(const std::string& terrain,
                            const std::vector<TruthCheckSample>& samples) {
  TruthCheckSummary summary;
  summary.terrain = terrain;
  summary.samples = static_cast<int>(samples.size());
  for (const TruthCheckSample& sample : samples) {
    if (sample.predicted_traversable) ++summary.predicted_traversable;
    if (!sample.Agrees()) continue;
    if (sample.predicted_traversable) {
      ++summary.agree_traversable;
    } else {
      ++summary.agree_untraversable;
    }
  }
  return summary;
}

void WriteTruthCheck(const std::vector<std::pair<std::string, std::vector<TruthCheckSample>>>& runs,
                     const TruthCheckOptions& options, const OutputFolder& folder) {
  std::string csv =
      "terrain,x_m,y_m,yaw_rad,predicted_cost,predicted_traversable,limit,result,moved_m,"
      "max_tilt_deg,agrees\n";
  nlohmann::json summaries = nlohmann::json::array();
  for (const auto& [terrain, samples] : runs) {
    for (const TruthCheckSample& s : samples) {
      fmt::format_to(std::back_inserter(csv),
                     FMT_STRING("{},{:.4f},{:.4f},{:.4f},{:.4f},{},{},{},{:.4f},{:.2f},{}\n"),
                     terrain, s.x_m, s.y_m, s.yaw_rad, s.predicted_cost,
                     s.predicted_traversable ? 1 : 0, common::NameOf(s.limit),
                     common::NameOf(s.result), s.moved_m, s.max_tilt_deg, s.Agrees() ? 1 : 0);
    }
    const TruthCheckSummary summary = Summarize(terrain, samples);
    summaries.push_back({{"terrain", terrain},
                         {"samples", summary.samples},
                         {"predicted_traversable", summary.predicted_traversable},
                         {"agree_traversable", summary.agree_traversable},
                         {"agree_untraversable", summary.agree_untraversable},
                         {"agreement", summary.Agreement()}});
  }
  WriteTextFile(folder.File("truth_check.csv"), csv);
  const nlohmann::json json = {{"seed", options.terrain.seed},
                               {"samples_per_terrain", options.samples},
                               {"world_size_m", options.world_size_m},
                               {"drive_m", options.drive_m},
                               {"speed_m_s", options.speed_m_s},
                               {"time_limit_s", options.time_limit_s},
                               {"terrains", summaries}};
  WriteTextFile(folder.File("truth_check.json"), json.dump(2) + "\n");
}

}  // namespace trav::scenarios
