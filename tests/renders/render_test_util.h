#pragma once

#include <string>

#include <Eigen/Core>

#include "renders/image.h"
#include "sim/simulation.h"

namespace trav::renders::testing {

/// Path of the Scout Mini model in the source tree.
inline std::string RobotModelPath() { return std::string(TRAV_MODELS_DIR) + "/scout_mini.xml"; }

/// A 10 x 10 m flat world with the robot resting at `position_W`, yaw 0.
inline std::unique_ptr<sim::Simulation> FlatWorldWithRobotAt(const Eigen::Vector2d& position_W) {
  sim::TerrainConfig config;
  config.type = sim::TerrainType::kFlat;
  config.size_m = {10, 10};
  sim::WorldOptions options;
  options.robot_model_path = RobotModelPath();
  common::Pose2 start;
  start.position = position_W;
  auto simulation = std::make_unique<sim::Simulation>(sim::GenerateTerrain(config), start, options);
  for (int i = 0; i < 250; ++i) simulation->Step();
  return simulation;
}

/// The renderer tests' world: FlatWorldWithRobotAt's, with a steep mound (0.5 m high, 0.4 m in
/// radius) centred at `mound_W` and one standing pedestrian-sized violet capsule mover at
/// `mover_W`.
inline std::unique_ptr<sim::Simulation> WorldWithMoundAndMover(const Eigen::Vector2d& robot_W,
                                                               const Eigen::Vector2d& mound_W,
                                                               const Eigen::Vector2d& mover_W) {
  sim::TerrainConfig config;
  config.type = sim::TerrainType::kFlat;
  config.size_m = {10, 10};
  sim::TerrainWorld world = sim::GenerateTerrain(config);
  for (int iy = 0; iy < world.geometry.num_y; ++iy) {
    for (int ix = 0; ix < world.geometry.num_x; ++ix) {
      const double r = (world.geometry.CellCenter(ix, iy) - mound_W).norm();
      if (r < 0.4) world.height_m(ix, iy) = static_cast<float>(0.5 * (1.0 - r / 0.4));
    }
  }
  sim::MovingObstacle mover;
  mover.name = "walker";
  mover.rgba = Eigen::Vector4f(0.6f, 0.2f, 0.8f, 1.0f);  // violet: unlike the robot and overlays
  sim::ConstantVelocityMotion standing;
  standing.start_W = mover_W;
  mover.motion = standing;
  sim::WorldOptions options;
  options.robot_model_path = RobotModelPath();
  common::Pose2 start;
  start.position = robot_W;
  auto simulation = std::make_unique<sim::Simulation>(world, start, options,
                                                      std::vector<sim::MovingObstacle>{mover});
  for (int i = 0; i < 250; ++i) simulation->Step();
  return simulation;
}

/// Centroid (column, row) of the pixels for which `match(r, g, b)` holds, and their count.
template <typename Match>
std::pair<Eigen::Vector2d, int> Centroid(const Image& image, Match match) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.Pixel(x, y);
      if (match(p[0], p[1], p[2])) {
        sum += Eigen::Vector2d(x, y);
        ++count;
      }
    }
  }
  return {count > 0 ? Eigen::Vector2d(sum / count) : sum, count};
}

/// Standard deviation of the gray levels of an image (0 for a blank frame).
inline double GrayStandardDeviation(const Image& image) {
  double sum = 0.0, sum2 = 0.0;
  const int n = image.width * image.height;
  for (int i = 0; i < n; ++i) {
    const double gray = (image.rgb[3 * i] + image.rgb[3 * i + 1] + image.rgb[3 * i + 2]) / 3.0;
    sum += gray;
    sum2 += gray * gray;
  }
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}

/// The robot's red paint, lit or in shade.
inline bool IsRobotRed(int r, int g, int b) { return r > 120 && g < 70 && b < 70; }

}  // namespace trav::renders::testing
