#pragma once

#include <string>
#include <vector>

#include "common/random.h"
#include "sim/terrain.h"

namespace trav::sim::internal {

/// Places obstacles while keeping discs around the robot's start and goal free.
class ObstaclePlacer {
 public:
  ObstaclePlacer(TerrainWorld* world, std::vector<Eigen::Vector2d> keep_clear_W,
                 double keep_clear_radius_m);

  /// True if a disc of `radius_m` at p_W lies inside the world and clear of the keep-clear discs.
  bool IsFree(const Eigen::Vector2d& p_W, double radius_m) const;

  /// True if the axis-aligned rectangle (centre, half extents) lies inside the world and clear of
  /// the keep-clear discs.
  bool IsRectangleFree(const Eigen::Vector2d& centre_W, const Eigen::Vector2d& half_m) const;

  /// Uniform random position inside the world, `margin_m` from its border.
  Eigen::Vector2d RandomPosition(common::Random* random, double margin_m) const;

  /// Lowest ground height under a disc of `radius_m` at p_W [m] (centre and 8 points on the rim).
  double MinGroundHeight(const Eigen::Vector2d& p_W, double radius_m) const;

  /// Adds an obstacle named "<kind>_<n>" (n counts per kind).
  void Add(const std::string& kind, Obstacle obstacle);

  /// Adds a vertical box wall from a_W to b_W (ground level to `height_m`), leaving the intervals
  /// that pass through keep-clear discs and the given door intervals (distances along the wall
  /// [m], each [begin, end]) open.
  void AddWall(const Eigen::Vector2d& a_W, const Eigen::Vector2d& b_W, double height_m,
               double thickness_m, std::vector<std::array<double, 2>> openings,
               const Eigen::Vector4f& rgba);

  TerrainWorld& world() { return *world_; }
  const TerrainWorld& world() const { return *world_; }

 private:
  TerrainWorld* world_;
  std::vector<Eigen::Vector2d> keep_clear_W_;
  double keep_clear_radius_m_;
  std::vector<std::pair<std::string, int>> counts_;
};

/// Hilly ground from `config.hilly` into world->height_m (geometry already set).
void FillHillyGround(const TerrainConfig& config, common::Random* random, TerrainWorld* world);

/// Scene generators (terrain_scenes.cc); each sets the ground and adds obstacles.
void GenerateForest(const TerrainConfig& config, common::Random* random, ObstaclePlacer* placer);
void GenerateRuin(const TerrainConfig& config, common::Random* random, ObstaclePlacer* placer);
void GenerateRoad(const TerrainConfig& config, common::Random* random, ObstaclePlacer* placer);
void GenerateIndoor(const TerrainConfig& config, common::Random* random, ObstaclePlacer* placer);

/// A pose at p_W (with z) rotated by yaw about z, then tilted by `tilt` about the rotated x axis.
Eigen::Isometry3d PoseAt(const Eigen::Vector3d& p_W, double yaw, double tilt = 0.0);

}  // namespace trav::sim::internal
