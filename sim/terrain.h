#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/archive.h"
#include "common/enum_names.h"
#include "common/grid.h"
#include "common/mesh.h"
#include "common/point_cloud.h"
#include "sim/noise.h"

namespace trav::sim {

/// Terrain families: the paper's five scene types plus test terrains.
enum class TerrainType {
  kFlat,
  kSlope,
  kStep,
  kStairs,
  kHilly,
  kForest,
  kRuin,
  kRoad,
  kIndoor,
  kHeightmap,
  kMesh,
};

/// The names of TerrainType's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<TerrainType>, 11> kTerrainTypeNames{
    {{TerrainType::kFlat, "flat"},
     {TerrainType::kSlope, "slope"},
     {TerrainType::kStep, "step"},
     {TerrainType::kStairs, "stairs"},
     {TerrainType::kHilly, "hilly"},
     {TerrainType::kForest, "forest"},
     {TerrainType::kRuin, "ruin"},
     {TerrainType::kRoad, "road"},
     {TerrainType::kIndoor, "indoor"},
     {TerrainType::kHeightmap, "heightmap"},
     {TerrainType::kMesh, "mesh"}}};
constexpr const auto& EnumNames(TerrainType) { return kTerrainTypeNames; }

/// Hilly ground (also the base of forest and ruin): fractal noise rescaled so that a chosen
/// percentile of the slope reaches a target angle.
struct HillyParams {
  FractalParams fractal{};    ///< noise family and octaves
  double wavelength_m{18.0};  ///< wavelength of the base octave [m], > 0
  double slope_p95_deg{
      12.0};  ///< 95th percentile of the ground slope after rescaling [deg], in [0, 45)
  double roughness_m{0.02};      ///< amplitude of the fine uniform bumps added on top [m], >= 0
  double roughness_cell_m{0.2};  ///< size of a roughness bump [m], >= resolution

  /// The keys of `terrain.parameters` for hilly, forest and ruin ground (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Enum("family", &fractal.family);
    a->Field("octaves", &fractal.octaves, {1, 16});
    a->Field("lacunarity", &fractal.lacunarity, {1, 8});
    a->Field("gain", &fractal.gain, {0, 1});
    a->Field("warp", &fractal.warp, {0, 100});
    a->Field("wavelength", &wavelength_m, {0.5, 1000});
    a->Field("slope_p95_deg", &slope_p95_deg, {0, 80});
    a->Field("roughness", &roughness_m, {0, 2});
    a->Field("roughness_cell", &roughness_cell_m, {0.01, 10});
  }
};

/// Forest: trees (trunk cylinders that collide, canopies that only the LiDAR and the camera see) on
/// hilly ground, placed by Poisson-disk sampling.
struct ForestParams {
  double tree_density_per_m2{0.08};                 ///< trees per m^2, in (0, 1]
  std::array<double, 2> trunk_radius_m{0.08, 0.3};  ///< [min, max] [m]
  std::array<double, 2> trunk_height_m{3.0, 8.0};   ///< [min, max] above ground [m]
  bool canopy{true};                                ///< add canopy spheres

  /// The forest's own keys of `terrain.parameters` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("tree_density", &tree_density_per_m2, {0, 0.5});
    a->Field("trunk_radius", &trunk_radius_m, {0.01, 2});
    a->Field("trunk_height", &trunk_height_m, {0.1, 50});
    a->Field("canopy", &canopy);
  }
};

/// Ruin: boxes (random yaw, tilted, partly buried), standing and fallen columns, low walls with
/// gaps and small rubble on hilly ground.
struct RuinParams {
  int num_boxes{40};
  int num_columns{20};
  int num_walls{10};
  int num_rubble{60};
  double burial_fraction_max{0.4};  ///< largest buried fraction of a box's height, in [0, 0.9]

  /// The ruin's own keys of `terrain.parameters` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("num_boxes", &num_boxes, {0, 2000});
    a->Field("num_columns", &num_columns, {0, 2000});
    a->Field("num_walls", &num_walls, {0, 2000});
    a->Field("num_rubble", &num_rubble, {0, 20000});
    a->Field("burial_fraction_max", &burial_fraction_max, {0, 1});
  }
};

/// Road: a street grid with raised sidewalks behind curbs, building blocks and poles.
struct RoadParams {
  double block_size_m{20.0};   ///< spacing of the streets [m]
  double street_width_m{7.0};  ///< road surface width between the curbs [m]
  double sidewalk_width_m{2.5};
  double curb_height_m{0.12};  ///< sidewalk height above the road [m]
  double camber{0.02};         ///< cross slope of the road surface (rise over run)
  int poles_per_block{4};

  /// The keys of `terrain.parameters` for roads (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("block_size", &block_size_m, {5, 500});
    a->Field("street_width", &street_width_m, {1, 100});
    a->Field("sidewalk_width", &sidewalk_width_m, {0, 50});
    a->Field("curb_height", &curb_height_m, {0, 1});
    a->Field("camber", &camber, {0, 0.5});
    a->Field("poles_per_block", &poles_per_block, {0, 100});
  }
};

/// Indoor: rooms split by binary space partitioning, walls with doorways, furniture and a ceiling.
struct IndoorParams {
  double min_room_size_m{4.0};
  double wall_height_m{2.7};
  double wall_thickness_m{0.1};
  double door_width_m{1.0};  ///< >= 0.8 so the robot fits
  int furniture_per_room{2};

  /// The keys of `terrain.parameters` for indoor worlds (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("min_room_size", &min_room_size_m, {1, 100});
    a->Field("wall_height", &wall_height_m, {0.1, 20});
    a->Field("wall_thickness", &wall_thickness_m, {0.02, 5});
    a->Field("door_width", &door_width_m, {0.2, 50});
    a->Field("furniture_per_room", &furniture_per_room, {0, 50});
  }
};

/// Ground from a file, such as the heightmap.png or heightmap.raw that `trav terrain` writes: its
/// samples span the terrain's `size` (the first and last sample of a row on the world's borders)
/// and are interpolated bilinearly onto the terrain's grid, so a file of the grid's own sample
/// counts gives its heights exactly.
struct HeightmapParams {
  /// A grayscale PNG (16 bits, or fewer scaled to 16; top row = largest y, MuJoCo's convention)
  /// or a `.raw` file of float32 heights [m] (little-endian, rows along +y from the smallest y).
  /// A relative path is taken from the scenario file's folder.
  std::string file;
  std::array<double, 2> height_range_m{0.0, 1.0};  ///< PNG: the heights of 0 and of 65535 [m]
  Eigen::Vector2d samples{0.0, 0.0};  ///< .raw: samples along x and y (whole numbers >= 2)
  /// The file's heights [m], (samples along x, samples along y), column iy at increasing y. Read
  /// by the scenario loader (scenarios/run/terrain_files.h): sim reads no files.
  Eigen::MatrixXf heights_m;

  /// The keys of `terrain.parameters` for a heightmap (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("file", &file);
    a->Field("height_range", &height_range_m, {-10000.0, 10000.0});
    a->Field("samples", &samples, {0.0, 4096.0});
  }
};

/// Ground from a triangle mesh file (OBJ, STL or PLY) in W [m], z up: its top surface, the highest
/// triangle over each height sample, becomes the height field that MuJoCo collides with and the
/// LiDAR sees (MuJoCo 2.2 collides a mesh geom as its convex hull, so a terrain cannot be one).
/// The mesh must cover the terrain's `size`.
struct MeshGroundParams {
  /// The mesh file; a relative path is taken from the scenario file's folder.
  std::string file;
  /// The file's triangles in W [m]. Read by the scenario loader (scenarios/run/terrain_files.h):
  /// sim reads no files.
  common::TriangleMesh mesh_W;

  /// The keys of `terrain.parameters` for a mesh (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("file", &file);
  }
};

/// Test terrains.
struct SlopeParams {
  double angle_deg{20.0};  ///< incline of the ramp rising along +x [deg], in [0, 60]
  double start_x_m{2.0};   ///< x where the ramp starts [m]; flat before it

  /// The keys of `terrain.parameters` for a slope (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("angle_deg", &angle_deg, {-60, 60});
    a->Field("start_x", &start_x_m, {-1000.0, 1000.0});
  }
};
struct StepParams {
  double height_m{0.2};  ///< height of the step [m]
  double x_m{2.0};       ///< x of the step edge [m]; the ground is higher for x > x_m

  /// The keys of `terrain.parameters` for a step (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("height", &height_m, {-5, 5});
    a->Field("x", &x_m, {-1000.0, 1000.0});
  }
};
struct StairsParams {
  double step_height_m{0.05};
  double step_depth_m{0.6};
  int num_steps{5};
  double start_x_m{2.0};

  /// The keys of `terrain.parameters` for stairs (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("step_height", &step_height_m, {0.005, 2});
    a->Field("step_depth", &step_depth_m, {0.05, 20});
    a->Field("num_steps", &num_steps, {1, 1000});
    a->Field("start_x", &start_x_m, {-1000.0, 1000.0});
  }
};

/// A box placed by hand on the generated ground (walls, closed rooms, barriers of purpose-built
/// scenarios): it stands on the ground at its centre, sunk 0.1 m so that no gap shows on slopes.
struct PlacedBox {
  std::string name;                                           ///< obstacle name "placed_<name>"
  Eigen::Vector2d centre_W{Eigen::Vector2d::Zero()};          ///< [m]
  Eigen::Vector2d half_extents_m{Eigen::Vector2d(0.5, 0.1)};  ///< along its x and y [m], > 0
  double height_m{1.0};                                       ///< above the ground [m], > 0
  double yaw_rad{0.0};                                        ///< [rad]

  /// The keys of an item of scenario section `terrain.boxes` (common/archive.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Field("name", &name);
    a->Field("centre", &centre_W, {-1000.0, 1000.0});
    a->Field("half_extents", &half_extents_m, {0.005, 500.0});
    a->Field("height", &height_m, {0.005, 100.0});
    a->Field("yaw", &yaw_rad, {-10.0, 10.0});
  }
};

/// Everything that defines a procedural world; the same config and seed give a bit-identical world.
struct TerrainConfig {
  TerrainType type{TerrainType::kHilly};
  std::uint64_t seed{1};
  Eigen::Vector2d size_m{50.0, 50.0};  ///< extent along x and y [m], centred on the world origin
  double resolution_m{0.1};            ///< height sample spacing [m], > 0
  HillyParams hilly{};
  ForestParams forest{};
  RuinParams ruin{};
  RoadParams road{};
  IndoorParams indoor{};
  SlopeParams slope{};
  StepParams step{};
  StairsParams stairs{};
  HeightmapParams heightmap{};
  MeshGroundParams mesh{};
  std::vector<PlacedBox> boxes;  ///< added after generation, not kept clear of start and goal

  /// The keys of scenario section `terrain` (common/archive.h); `parameters` holds the keys of the
  /// chosen type only.
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Enum("type", &type);
    a->Field("seed", &seed);
    a->Field("size", &size_m, {2, 500});
    a->Field("resolution", &resolution_m, {0.02, 1.0});
    a->Map("parameters", [this](Archive& p) { SerializeParameters(&p); });
    a->Sequence("boxes", &boxes, 10000);
  }

  /// The keys of `terrain.parameters` for `type`.
  template <typename Archive>
  void SerializeParameters(Archive* a) {
    switch (type) {
      case TerrainType::kFlat:
        break;
      case TerrainType::kSlope:
        slope.Serialize(a);
        break;
      case TerrainType::kStep:
        step.Serialize(a);
        break;
      case TerrainType::kStairs:
        stairs.Serialize(a);
        break;
      case TerrainType::kRoad:
        road.Serialize(a);
        break;
      case TerrainType::kIndoor:
        indoor.Serialize(a);
        break;
      case TerrainType::kHilly:
        hilly.Serialize(a);
        break;
      case TerrainType::kForest:
        hilly.Serialize(a);
        forest.Serialize(a);
        break;
      case TerrainType::kRuin:
        hilly.Serialize(a);
        ruin.Serialize(a);
        break;
      case TerrainType::kHeightmap:
        heightmap.Serialize(a);
        break;
      case TerrainType::kMesh:
        mesh.Serialize(a);
        break;
    }
  }
};

// Obstacles are common primitives.
using common::ShapeType;
using common::TriangleMesh;

/// How an obstacle takes part in the simulation.
enum class ObstacleRole {
  kSolid,    ///< collides, seen by the LiDAR, rendered
  kCanopy,   ///< seen by the LiDAR and rendered; no collision (tree crowns)
  kCeiling,  ///< collides and seen by the LiDAR; hidden in videos so the camera can look in
};

/// A static obstacle: a primitive (shape, pose X_WO, size) with a name, a role and a colour.
struct Obstacle : common::Primitive {
  std::string
      name;  ///< unique in the world; its prefix names the kind ("tree", "box", "wall", ...)
  ObstacleRole role{ObstacleRole::kSolid};
  Eigen::Vector4f rgba{0.6f, 0.6f, 0.6f, 1.0f};
};

/// A generated world: a height field (the ground) and obstacle primitives.
struct TerrainWorld {
  TerrainConfig config{};
  common::GridGeometry geometry{};  ///< height samples; cell (ix, iy) is one sample
  Eigen::MatrixXf height_m;         ///< ground height at each sample [m], (num_x, num_y)
  std::vector<Obstacle> obstacles;

  /// Ground height at p_W by bilinear interpolation [m] (obstacles not included).
  double GroundHeight(const Eigen::Vector2d& p_W) const;
};

/// Generates the world of `config`. Obstacles are kept at least `keep_clear_radius_m` away from
/// every point of `keep_clear_W` (robot start, goal).
/// @throws common::InputError if the config is inconsistent (names the field and value).
TerrainWorld GenerateTerrain(const TerrainConfig& config,
                             const std::vector<Eigen::Vector2d>& keep_clear_W = {},
                             double keep_clear_radius_m = 2.0);

/// Checks ranges of a terrain config. @throws common::InputError naming the field and value.
void ValidateTerrainConfig(const TerrainConfig& config);

/// Statistics of a generated world, used to document and test each type's ranges.
struct TerrainStatistics {
  double slope_p50_deg{0.0};  ///< median ground slope [deg]
  double slope_p95_deg{0.0};  ///< 95th percentile ground slope [deg]
  double slope_max_deg{0.0};
  double height_min_m{0.0};
  double height_max_m{0.0};
  int num_obstacles{0};             ///< solid obstacles (ceiling excluded)
  int num_trees{0};                 ///< obstacles named "tree..._trunk"
  double tree_density_per_m2{0.0};  ///< trees per m^2 of the world's area
};

/// Computes the statistics of a world (slopes from central differences of the height samples).
TerrainStatistics ComputeStatistics(const TerrainWorld& world);

}  // namespace trav::sim
