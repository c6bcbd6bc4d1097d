#pragma once

#include <vector>

#include "common/grid.h"
#include "common/point_cloud.h"
#include "sim/lidar/ray_scene.h"
#include "sim/moving_obstacles.h"
#include "sim/terrain.h"

namespace trav::sim {

/// The ground as triangles in W, two per height-field cell (for ray casting and export).
TriangleMesh GroundMesh(const TerrainWorld& world);

/// The obstacle primitives as triangles in W (common::PrimitiveMesh of each).
TriangleMesh ObstacleMesh(const std::vector<Obstacle>& obstacles, int segments = 16);

/// A dense noise-free point cloud of the world in W: the ground at every height sample and the
/// obstacle surfaces sampled every `spacing_m` or closer (parts below the ground are dropped).
/// Used for ground truth and export.
common::PointCloud DenseCloud(const TerrainWorld& world, double spacing_m);

/// Height above the ground [m] of the solid obstacles' surfaces on the world's height grid: per
/// cell the highest obstacle surface point up to `max_height_m` above the ground (higher parts,
/// such as tree crowns and ceilings, do not touch the robot), 0 where there is none. Surfaces are
/// sampled every half cell. Input of the ground-truth traversability.
Eigen::MatrixXf ObstacleHeightGrid(const TerrainWorld& world, double max_height_m = 1.0);

/// A grid of obstacle tops finer than the world's height field.
struct ObstacleRaster {
  common::GridGeometry geometry;
  Eigen::MatrixXf top_m;  ///< (num_x, num_y) of `geometry`: height in W [m], NaN where none
};

/// Height in W [m] of the highest solid obstacle material within `band_m` above the ground, on the
/// vertical line through each centre of a grid over the world with cells of `resolution_m` (exact:
/// common::VerticalExtent, the ground bilinear); NaN where there is none.
/// Material wholly above the band (a table top or a crown above the robot) is left out: the robot
/// passes under it. Input of the physical ground truth (mapping::ComputePhysicalTruth), with the
/// robot's height as the band.
ObstacleRaster ObstacleBandRaster(const TerrainWorld& world, double band_m, double resolution_m);

/// What the LiDAR sees of the world: the ground at full height-field resolution (object 0), every
/// obstacle as a primitive (objects 1.., in the order of `world.obstacles`), tree crowns and
/// ceilings included, and every mover as a moving mesh in its frame O (moving object i is
/// movers[i], object id 1 + world.obstacles.size() + i), placed at its pose at t = 0: move it with
/// RayScene::SetMovingPose(i, X_WO). The robot is not part of it, so it never sees itself. Each
/// object carries its diffuse reflectance (GroundReflectance, ObstacleReflectance,
/// MoverReflectance).
lidar::RaySceneDescription RaySceneOf(const TerrainWorld& world,
                                      const std::vector<MovingObstacle>& movers = {});

/// Diffuse reflectance at 905 nm (the MID-360's wavelength) of the ground of a terrain type:
/// grass (hilly, slope) 0.5, forest floor 0.25, rubble and dust (ruin) 0.3, asphalt (road) 0.12,
/// concrete (flat, step, stairs) 0.35, indoor floor 0.4. Rounded typical values (vegetation is
/// bright in the near infrared, asphalt dark), not measurements (docs/lidar.md).
float GroundReflectance(TerrainType type);

/// Diffuse reflectance of an obstacle by its kind, the prefix of its name: tree (bark) 0.35,
/// canopy (leaves) 0.5, box and riser (concrete) 0.35, column (stone) 0.35, rubble 0.3, wall
/// (painted) 0.7, ceiling 0.8, pole (painted metal) 0.45, furniture, table, table_leg (wood) 0.45;
/// anything else lidar::kDefaultReflectance.
float ObstacleReflectance(const std::string& name);

/// Diffuse reflectance of a mover: 0.35 for a capsule (a pedestrian's clothes), 0.45 for a box or
/// cylinder (a cart, a crate).
float MoverReflectance(const MovingObstacle& mover);

}  // namespace trav::sim
