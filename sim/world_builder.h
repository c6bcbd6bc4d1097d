#pragma once

#include <string>
#include <vector>

#include "sim/moving_obstacles.h"
#include "sim/terrain.h"

namespace trav::sim {

/// Settings of the MuJoCo world that are not part of the terrain.
struct WorldOptions {
  std::string robot_model_path;  ///< absolute path of the robot MJCF (models/scout_mini.xml)
  double ground_friction{0.9};   ///< sliding friction of the ground; it wins MuJoCo's max rule
  double timestep_s{0.002};      ///< physics step [s], > 0
  /// Samples per axis of the rendered ground, at most. The ground collides with the full height
  /// field but is drawn from a bilinear resampling of it: llvmpipe's frame time grows with the
  /// triangle count, and 501 x 501 samples cost about 4x a 126 x 126 copy (README, performance).
  int visual_max_samples{126};
  /// Empty: both height fields get their samples from memory after loading (FillHeightField).
  /// Else the name of a MuJoCo binary height-field file (WriteHeightFieldFile) that both read: a
  /// world.xml that MuJoCo's `simulate` opens on its own (ExportWorld).
  std::string height_field_file;
};

/// Collision classes (MuJoCo contype bits). Two geoms collide when the contype of either shares a
/// bit with the conaffinity of the other; every colliding geom has conaffinity kCollidesWithRobot,
/// so everything collides with the robot and nothing else collides with anything: movers are
/// kinematic and pass through the ground, the static obstacles and each other.
constexpr int kRobotContype = 1;       ///< the robot's geoms (MJCF default contype 1)
constexpr int kStaticContype = 2;      ///< ground and static obstacles
constexpr int kMoverContype = 4;       ///< moving obstacles
constexpr int kCollidesWithRobot = 1;  ///< conaffinity of every colliding geom

/// The drawn ground's texture: stretched once over the terrain (texrepeat 1 1), a flat colour
/// until a renderer paints it (renders/ground_texture.h). Square, this many texels a side.
constexpr const char* kGroundTextureName = "ground_colors";
constexpr int kGroundTextureSize = 1024;

/// The MJCF text of a world: the robot included from its file; the ground as a height field named
/// "terrain" that collides (geom group 3, not drawn) and a coarser copy "terrain_visual" that is
/// drawn and does not collide (their samples are filled from memory after loading, see
/// FillHeightField) with the material "ground" (texture kGroundTextureName); obstacles as geoms
/// named after them (canopies visual-only, the ceiling in geom group 4 so videos can hide it); each
/// mover as a mocap body "mover_<name>" holding one geom of the same name (group 0), placed at its
/// pose at t = 0. Movers are not validated here (see ValidateMovingObstacles).
std::string BuildWorldXml(const TerrainWorld& world, const WorldOptions& options,
                          const std::vector<MovingObstacle>& movers = {});

/// Height-field layout in MuJoCo: samples normalised to [0, 1], scaled by `z_top_m`, placed at
/// `z_offset_m` (the geom's z), as MuJoCo 2.2's hfield asset defines it.
struct HeightFieldLayout {
  double z_offset_m{0.0};  ///< ground height of a sample with value 0 [m]
  double z_top_m{1.0};     ///< height of a sample with value 1 above z_offset [m], > 0
};

/// The normalisation used for `world` (minimum height and range, at least 1 mm).
HeightFieldLayout ComputeHeightFieldLayout(const TerrainWorld& world);

/// The ground heights resampled (bilinearly) to at most `max_samples` per axis, evenly over the
/// same extent, as a (num_x, num_y) matrix; the world's own heights if they are not larger.
Eigen::MatrixXf ResampleGround(const TerrainWorld& world, int max_samples);

/// Writes the normalised samples of `height_m` (num_x, num_y) into `data` (row-major, rows along y,
/// num_x * num_y), MuJoCo's hfield_data layout.
void FillHeightField(const Eigen::MatrixXf& height_m, const HeightFieldLayout& layout, float* data);

/// Writes the world's ground as MuJoCo's custom binary height field (int32 nrow, int32 ncol, then
/// nrow * ncol float32 samples, rows along y), normalised as ComputeHeightFieldLayout says.
/// @throws std::runtime_error naming the file if it cannot be written.
void WriteHeightFieldFile(const TerrainWorld& world, const std::string& path);

/// Writes `folder`/world.xml and its height field `folder`/terrain.bin: the world a run simulated
/// (terrain, obstacles, movers at t = 0 and the robot: a copy `folder`/robot.xml of a robot file
/// that names no other file, else its path relative to `folder`), which MuJoCo's
/// `simulate world.xml` opens. @throws std::runtime_error naming a file that cannot be written.
void ExportWorld(const TerrainWorld& world, const WorldOptions& options,
                 const std::vector<MovingObstacle>& movers, const std::string& folder);

}  // namespace trav::sim
