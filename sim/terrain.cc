#include "sim/terrain.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/input_error.h"
#include "sim/terrain_internal.h"

namespace trav::sim {
namespace {

using common::InputError;

constexpr double kDegToRad = M_PI / 180.0;

// Slope magnitude |grad h| at every interior sample, by central differences.
std::vector<double> SlopeMagnitudes(const TerrainWorld& world) {
  std::vector<double> slopes;
  const Eigen::MatrixXf& h = world.height_m;
  const double two_res = 2.0 * world.geometry.resolution_m;
  slopes.reserve(
      static_cast<std::size_t>(std::max<Eigen::Index>(0, (h.rows() - 2) * (h.cols() - 2))));
  for (Eigen::Index iy = 1; iy + 1 < h.cols(); ++iy) {
    for (Eigen::Index ix = 1; ix + 1 < h.rows(); ++ix) {
      const double gx = (h(ix + 1, iy) - h(ix - 1, iy)) / two_res;
      const double gy = (h(ix, iy + 1) - h(ix, iy - 1)) / two_res;
      slopes.push_back(std::hypot(gx, gy));
    }
  }
  return slopes;
}

double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// The heightmap's samples, spanning the world, interpolated bilinearly at every height sample;
// a heightmap of the grid's own sample counts is copied exactly (u is then a whole number).
void FillFromHeightmap(const HeightmapParams& heightmap, TerrainWorld* world) {
  const Eigen::MatrixXf& source = heightmap.heights_m;
  const common::GridGeometry& g = world->geometry;
  auto position = [](int i, int n_grid, Eigen::Index n_source, Eigen::Index* i0, double* frac) {
    const double u = n_grid > 1 ? static_cast<double>(i) * static_cast<double>(n_source - 1) /
                                      static_cast<double>(n_grid - 1)
                                : 0.0;
    *i0 = std::min<Eigen::Index>(static_cast<Eigen::Index>(std::floor(u)), n_source - 2);
    *frac = u - static_cast<double>(*i0);
  };
  for (int iy = 0; iy < g.num_y; ++iy) {
    Eigen::Index j0;
    double fy;
    position(iy, g.num_y, source.cols(), &j0, &fy);
    for (int ix = 0; ix < g.num_x; ++ix) {
      Eigen::Index i0;
      double fx;
      position(ix, g.num_x, source.rows(), &i0, &fx);
      const double low = (1.0 - fx) * source(i0, j0) + fx * source(i0 + 1, j0);
      const double high = (1.0 - fx) * source(i0, j0 + 1) + fx * source(i0 + 1, j0 + 1);
      world->height_m(ix, iy) = static_cast<float>((1.0 - fy) * low + fy * high);
    }
  }
}

// The mesh's top surface at every sample of `g`: the highest of the triangles whose xy projection
// holds the sample (vertical triangles hold none); NaN under no triangle.
Eigen::MatrixXf MeshTopSurface(const common::TriangleMesh& mesh, const common::GridGeometry& g) {
  Eigen::MatrixXf h =
      Eigen::MatrixXf::Constant(g.num_x, g.num_y, std::numeric_limits<float>::quiet_NaN());
  constexpr double kInside = -1e-9;  // barycentric tolerance: samples on a shared edge count
  // the samples whose index along an axis lies in [low, high] of a coordinate
  auto first = [](double low, double origin, double resolution) {
    return static_cast<int>(std::ceil((low - origin) / resolution - 1e-9));
  };
  auto last = [](double high, double origin, double resolution) {
    return static_cast<int>(std::floor((high - origin) / resolution + 1e-9));
  };
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.col(mesh.triangles(0, t)).cast<double>();
    const Eigen::Vector3d b = mesh.vertices.col(mesh.triangles(1, t)).cast<double>();
    const Eigen::Vector3d c = mesh.vertices.col(mesh.triangles(2, t)).cast<double>();
    const double area2 = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(area2) < 1e-12) continue;
    const Eigen::Vector2d low = a.head<2>().cwiseMin(b.head<2>()).cwiseMin(c.head<2>());
    const Eigen::Vector2d high = a.head<2>().cwiseMax(b.head<2>()).cwiseMax(c.head<2>());
    const int x0 = std::max(0, first(low.x(), g.origin_W.x(), g.resolution_m));
    const int x1 = std::min(g.num_x - 1, last(high.x(), g.origin_W.x(), g.resolution_m));
    const int y0 = std::max(0, first(low.y(), g.origin_W.y(), g.resolution_m));
    const int y1 = std::min(g.num_y - 1, last(high.y(), g.origin_W.y(), g.resolution_m));
    for (int iy = y0; iy <= y1; ++iy) {
      for (int ix = x0; ix <= x1; ++ix) {
        const Eigen::Vector2d p = g.CellCenter(ix, iy);
        // barycentric weights of b and c
        const double wb =
            ((p.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (p.y() - a.y())) / area2;
        const double wc =
            ((b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y())) / area2;
        if (wb < kInside || wc < kInside || 1.0 - wb - wc < kInside) continue;
        const auto z = static_cast<float>(a.z() + wb * (b.z() - a.z()) + wc * (c.z() - a.z()));
        if (!(h(ix, iy) >= z)) h(ix, iy) = z;  // NaN (not yet covered) or lower
      }
    }
  }
  return h;
}

// Test terrains: analytic height profiles along x. A height field can only ramp between two
// samples, so every step edge also gets a riser box over that ramp: its face is vertical, as a real
// curb or stair.
void FillProfile(const TerrainConfig& config, internal::ObstaclePlacer* placer) {
  TerrainWorld& world = placer->world();
  const common::GridGeometry& g = world.geometry;
  for (int ix = 0; ix < g.num_x; ++ix) {
    const double x = g.CellCenter(ix, 0).x();
    double h = 0.0;
    switch (config.type) {
      case TerrainType::kSlope:
        h = std::max(0.0, x - config.slope.start_x_m) *
            std::tan(config.slope.angle_deg * kDegToRad);
        break;
      case TerrainType::kStep:
        h = x > config.step.x_m ? config.step.height_m : 0.0;
        break;
      case TerrainType::kStairs: {
        const double steps =
            std::floor((x - config.stairs.start_x_m) / config.stairs.step_depth_m) + 1.0;
        h = config.stairs.step_height_m * std::clamp(steps, 0.0, double(config.stairs.num_steps));
        break;
      }
      default:
        break;
    }
    world.height_m.row(ix).setConstant(static_cast<float>(h));
  }
  auto add_riser = [&](double edge_x, double top_z) {
    // from the edge to the first sample beyond it, across the whole world
    const double next_sample =
        g.origin_W.x() +
        g.resolution_m * (std::floor((edge_x - g.origin_W.x()) / g.resolution_m) + 1.0);
    Obstacle riser;
    riser.shape = ShapeType::kBox;
    riser.size =
        Eigen::Vector3d(0.5 * (next_sample - edge_x), 0.5 * g.Extent().y(), 0.5 * top_z + 0.05);
    riser.X_WO.translation() =
        Eigen::Vector3d(0.5 * (edge_x + next_sample), g.Center().y(), 0.5 * top_z - 0.05);
    riser.rgba = Eigen::Vector4f(0.6f, 0.6f, 0.6f, 1.0f);
    if (riser.size.x() > 1e-6 && top_z > 0.0) placer->Add("riser", riser);
  };
  if (config.type == TerrainType::kStep) add_riser(config.step.x_m, config.step.height_m);
  if (config.type == TerrainType::kStairs) {
    for (int k = 0; k < config.stairs.num_steps; ++k) {
      add_riser(config.stairs.start_x_m + k * config.stairs.step_depth_m,
                (k + 1) * config.stairs.step_height_m);
    }
  }
}

}  // namespace

double TerrainWorld::GroundHeight(const Eigen::Vector2d& p_W) const {
  return common::InterpolateBilinear(geometry, height_m, p_W);
}

namespace {

void ValidateHilly(const TerrainConfig& c) {
  const HillyParams& h = c.hilly;
  common::RequireValue(h.fractal.octaves >= 1 && h.fractal.octaves <= 12, "parameters.octaves",
                       h.fractal.octaves, "must be in [1, 12]");
  common::RequireValue(h.fractal.lacunarity > 1.0, "parameters.lacunarity", h.fractal.lacunarity,
                       "must be > 1");
  common::RequireValue(h.fractal.gain > 0.0 && h.fractal.gain < 1.0, "parameters.gain",
                       h.fractal.gain, "must be in (0, 1)");
  common::RequireValue(h.fractal.warp >= 0.0, "parameters.warp", h.fractal.warp, "must be >= 0");
  common::RequireValue(h.wavelength_m > 0.0, "parameters.wavelength", h.wavelength_m,
                       "must be > 0");
  common::RequireValue(h.slope_p95_deg >= 0.0 && h.slope_p95_deg < 45.0, "parameters.slope_p95_deg",
                       h.slope_p95_deg, "must be in [0, 45)");
  common::RequireValue(h.roughness_m >= 0.0, "parameters.roughness", h.roughness_m, "must be >= 0");
  common::RequireValue(h.roughness_cell_m >= c.resolution_m, "parameters.roughness_cell",
                       h.roughness_cell_m, "must be >= the resolution");
}

void ValidateForest(const ForestParams& f) {
  common::RequireValue(f.tree_density_per_m2 > 0.0 && f.tree_density_per_m2 <= 1.0,
                       "parameters.tree_density", f.tree_density_per_m2, "must be in (0, 1]");
  common::RequireValue(f.trunk_radius_m[0] > 0.0 && f.trunk_radius_m[0] <= f.trunk_radius_m[1],
                       "parameters.trunk_radius", f.trunk_radius_m[0],
                       "must be a range [min, max] with min > 0");
  common::RequireValue(f.trunk_height_m[0] > 0.0 && f.trunk_height_m[0] <= f.trunk_height_m[1],
                       "parameters.trunk_height", f.trunk_height_m[0],
                       "must be a range [min, max] with min > 0");
}

void ValidateRuin(const RuinParams& r) {
  common::RequireValue(
      r.num_boxes >= 0 && r.num_columns >= 0 && r.num_walls >= 0 && r.num_rubble >= 0, "parameters",
      std::min({r.num_boxes, r.num_columns, r.num_walls, r.num_rubble}),
      "obstacle counts must be >= 0");
  common::RequireValue(r.burial_fraction_max >= 0.0 && r.burial_fraction_max <= 0.9,
                       "parameters.burial_fraction_max", r.burial_fraction_max,
                       "must be in [0, 0.9]");
}

void ValidateRoad(const RoadParams& road) {
  common::RequireValue(road.street_width_m > 0.0, "parameters.street_width", road.street_width_m,
                       "must be > 0");
  common::RequireValue(road.block_size_m > road.street_width_m + 2.0 * road.sidewalk_width_m + 1.0,
                       "parameters.block_size", road.block_size_m,
                       "must exceed street_width + 2 sidewalk_width + 1 m");
  common::RequireValue(road.curb_height_m >= 0.0, "parameters.curb_height", road.curb_height_m,
                       "must be >= 0");
}

void ValidateIndoor(const IndoorParams& in) {
  common::RequireValue(in.door_width_m >= 0.8, "parameters.door_width", in.door_width_m,
                       "must be >= 0.8 m (the robot is 0.58 m wide)");
  common::RequireValue(in.min_room_size_m >= 2.0 * in.door_width_m, "parameters.min_room_size",
                       in.min_room_size_m, "must be >= twice the door width");
  common::RequireValue(in.wall_height_m > 0.5, "parameters.wall_height", in.wall_height_m,
                       "must be > 0.5 m");
  common::RequireValue(in.wall_thickness_m > 0.0, "parameters.wall_thickness", in.wall_thickness_m,
                       "must be > 0");
}

}  // namespace

void ValidateTerrainConfig(const TerrainConfig& c) {
  for (std::size_t i = 0; i < c.boxes.size(); ++i) {
    const PlacedBox& b = c.boxes[i];
    const std::string key = "boxes[" + std::to_string(i) + "].";
    common::RequireValue(b.half_extents_m.minCoeff() > 0.0, key + "half_extents",
                         b.half_extents_m.minCoeff(), "must be > 0");
    common::RequireValue(b.height_m > 0.0, key + "height", b.height_m, "must be > 0");
    for (std::size_t j = 0; j < i; ++j) {
      if (c.boxes[j].name == b.name) {
        throw common::InputError("", key + "name", "'" + b.name + "' is used twice");
      }
    }
  }
  common::RequireValue(c.resolution_m > 0.0, "resolution", c.resolution_m, "must be > 0");
  common::RequireValue(c.size_m.x() >= c.resolution_m, "size[0]", c.size_m.x(),
                       "must be at least one cell");
  common::RequireValue(c.size_m.y() >= c.resolution_m, "size[1]", c.size_m.y(),
                       "must be at least one cell");
  // what one run may hold in memory: 2048^2 height samples (with the ray-casting mesh and the
  // MuJoCo height field about 0.5 GB), and 20,000 generated obstacles
  const double samples =
      (c.size_m.x() / c.resolution_m + 1.0) * (c.size_m.y() / c.resolution_m + 1.0);
  common::RequireValue(samples <= 2048.0 * 2048.0, "resolution", c.resolution_m,
                       "gives more than 2048 x 2048 height samples for the terrain's size");
  const double area_m2 = c.size_m.x() * c.size_m.y();
  constexpr double kMaxObstacles = 20000.0;
  if (c.type == TerrainType::kForest) {
    common::RequireValue(c.forest.tree_density_per_m2 * area_m2 <= kMaxObstacles,
                         "parameters.tree_density", c.forest.tree_density_per_m2,
                         "gives more than 20000 trees on the terrain's size");
  }
  if (c.type == TerrainType::kRoad) {
    const double blocks = area_m2 / (c.road.block_size_m * c.road.block_size_m) + 4.0;
    common::RequireValue(blocks * c.road.poles_per_block <= kMaxObstacles,
                         "parameters.poles_per_block", c.road.poles_per_block,
                         "gives more than 20000 poles on the terrain's size");
  }
  if (c.type == TerrainType::kIndoor) {
    const double rooms = area_m2 / (c.indoor.min_room_size_m * c.indoor.min_room_size_m) + 4.0;
    common::RequireValue(rooms * c.indoor.furniture_per_room <= kMaxObstacles,
                         "parameters.furniture_per_room", c.indoor.furniture_per_room,
                         "gives more than 20000 pieces of furniture on the terrain's size");
  }
  const bool hilly = c.type == TerrainType::kHilly || c.type == TerrainType::kForest ||
                     c.type == TerrainType::kRuin;
  if (hilly) ValidateHilly(c);
  if (c.type == TerrainType::kForest) ValidateForest(c.forest);
  if (c.type == TerrainType::kRuin) ValidateRuin(c.ruin);
  if (c.type == TerrainType::kRoad) ValidateRoad(c.road);
  if (c.type == TerrainType::kIndoor) ValidateIndoor(c.indoor);
  if (c.type == TerrainType::kSlope) {
    common::RequireValue(c.slope.angle_deg >= 0.0 && c.slope.angle_deg <= 60.0,
                         "parameters.angle_deg", c.slope.angle_deg, "must be in [0, 60]");
  }
  if (c.type == TerrainType::kStep) {
    common::RequireValue(c.step.height_m >= 0.0, "parameters.height", c.step.height_m,
                         "must be >= 0");
  }
  if (c.type == TerrainType::kHeightmap) {
    const Eigen::MatrixXf& heights = c.heightmap.heights_m;
    const std::string file = common::QuotedExcerpt(c.heightmap.file);
    if (heights.rows() < 2 || heights.cols() < 2) {
      throw common::InputError("", "parameters.file",
                               file + " must hold at least 2 x 2 height samples (required)");
    }
    if (!heights.allFinite()) {
      throw common::InputError("", "parameters.file", file + " holds heights that are not finite");
    }
  }
  if (c.type == TerrainType::kMesh) {
    const std::string file = common::QuotedExcerpt(c.mesh.file);
    if (c.mesh.mesh_W.triangles.cols() == 0) {
      throw common::InputError("", "parameters.file", file + " holds no triangle (required)");
    }
    const Eigen::MatrixXf h = MeshTopSurface(
        c.mesh.mesh_W,
        common::GridGeometry::Centered(Eigen::Vector2d::Zero(), c.size_m, c.resolution_m));
    const Eigen::Index uncovered = h.size() - h.array().isFinite().count();
    if (uncovered > 0) {
      throw common::InputError("", "parameters.file",
                               file + " leaves " + std::to_string(uncovered) + " of " +
                                   std::to_string(h.size()) +
                                   " height samples under no triangle: its x, y extent must "
                                   "cover the terrain's size, centred on the origin");
    }
  }
  if (c.type == TerrainType::kStairs) {
    common::RequireValue(c.stairs.step_depth_m > 0.0, "parameters.step_depth",
                         c.stairs.step_depth_m, "must be > 0");
    common::RequireValue(c.stairs.num_steps >= 1, "parameters.num_steps", c.stairs.num_steps,
                         "must be >= 1");
    common::RequireValue(c.stairs.step_height_m >= 0.0, "parameters.step_height",
                         c.stairs.step_height_m, "must be >= 0");
  }
}

TerrainWorld GenerateTerrain(const TerrainConfig& config,
                             const std::vector<Eigen::Vector2d>& keep_clear_W,
                             double keep_clear_radius_m) {
  ValidateTerrainConfig(config);
  TerrainWorld world;
  world.config = config;
  world.geometry =
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), config.size_m, config.resolution_m);
  world.height_m = Eigen::MatrixXf::Zero(world.geometry.num_x, world.geometry.num_y);

  common::Random random(config.seed);
  internal::ObstaclePlacer placer(&world, keep_clear_W, keep_clear_radius_m);
  switch (config.type) {
    case TerrainType::kFlat:
      break;
    case TerrainType::kSlope:
    case TerrainType::kStep:
    case TerrainType::kStairs:
      FillProfile(config, &placer);
      break;
    case TerrainType::kHilly:
      internal::FillHillyGround(config, &random, &world);
      break;
    case TerrainType::kForest:
      internal::GenerateForest(config, &random, &placer);
      break;
    case TerrainType::kRuin:
      internal::GenerateRuin(config, &random, &placer);
      break;
    case TerrainType::kRoad:
      internal::GenerateRoad(config, &random, &placer);
      break;
    case TerrainType::kIndoor:
      internal::GenerateIndoor(config, &random, &placer);
      break;
    case TerrainType::kHeightmap:
      FillFromHeightmap(config.heightmap, &world);
      break;
    case TerrainType::kMesh:
      // ValidateTerrainConfig has checked that every sample lies under a triangle
      world.height_m = MeshTopSurface(config.mesh.mesh_W, world.geometry);
      break;
  }
  constexpr double kSunk_m = 0.1;
  for (const PlacedBox& box : config.boxes) {
    Obstacle obstacle;
    obstacle.name = "placed_" + box.name;
    obstacle.shape = ShapeType::kBox;
    obstacle.size = Eigen::Vector3d(box.half_extents_m.x(), box.half_extents_m.y(),
                                    0.5 * (box.height_m + kSunk_m));
    obstacle.X_WO.translation() << box.centre_W,
        world.GroundHeight(box.centre_W) - kSunk_m + obstacle.size.z();
    obstacle.X_WO.linear() =
        Eigen::AngleAxisd(box.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    obstacle.rgba = Eigen::Vector4f(0.55f, 0.5f, 0.45f, 1.0f);
    world.obstacles.push_back(std::move(obstacle));
  }
  return world;
}

namespace internal {

void FillHillyGround(const TerrainConfig& config, common::Random* random, TerrainWorld* world) {
  const HillyParams& params = config.hilly;
  const FractalNoise noise(random->Next(), params.fractal);
  Eigen::MatrixXf& h = world->height_m;
  for (int iy = 0; iy < world->geometry.num_y; ++iy) {
    for (int ix = 0; ix < world->geometry.num_x; ++ix) {
      const Eigen::Vector2d p = world->geometry.CellCenter(ix, iy) / params.wavelength_m;
      h(ix, iy) = static_cast<float>(noise.Evaluate(p));
    }
  }
  // rescale so that the 95th percentile of the slope is the target angle
  h.array() -= h.mean();
  const double p95 = Percentile(SlopeMagnitudes(*world), 0.95);
  const double target = std::tan(params.slope_p95_deg * kDegToRad);
  if (p95 > 0.0) h *= static_cast<float>(target / p95);

  // fine roughness: uniform bumps on a coarser lattice, interpolated bilinearly
  if (params.roughness_m > 0.0) {
    common::GridGeometry coarse = common::GridGeometry::Centered(
        world->geometry.Center(), world->geometry.Extent(), params.roughness_cell_m);
    Eigen::MatrixXf bumps(coarse.num_x, coarse.num_y);
    for (int iy = 0; iy < coarse.num_y; ++iy) {
      for (int ix = 0; ix < coarse.num_x; ++ix) {
        bumps(ix, iy) =
            static_cast<float>(random->Uniform(-params.roughness_m, params.roughness_m));
      }
    }
    for (int iy = 0; iy < world->geometry.num_y; ++iy) {
      for (int ix = 0; ix < world->geometry.num_x; ++ix) {
        h(ix, iy) += common::InterpolateBilinear(coarse, bumps, world->geometry.CellCenter(ix, iy));
      }
    }
  }
}

Eigen::Isometry3d PoseAt(const Eigen::Vector3d& p_W, double yaw, double tilt) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = p_W;
  X.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return X;
}

ObstaclePlacer::ObstaclePlacer(TerrainWorld* world, std::vector<Eigen::Vector2d> keep_clear_W,
                               double keep_clear_radius_m)
    : world_(world),
      keep_clear_W_(std::move(keep_clear_W)),
      keep_clear_radius_m_(keep_clear_radius_m) {}

bool ObstaclePlacer::IsFree(const Eigen::Vector2d& p_W, double radius_m) const {
  const Eigen::Vector2d low = world_->geometry.origin_W;
  const Eigen::Vector2d high = low + world_->geometry.Extent();
  if ((p_W.array() - radius_m < low.array()).any() ||
      (p_W.array() + radius_m > high.array()).any()) {
    return false;
  }
  for (const Eigen::Vector2d& c : keep_clear_W_) {
    if ((p_W - c).norm() < radius_m + keep_clear_radius_m_) return false;
  }
  return true;
}

bool ObstaclePlacer::IsRectangleFree(const Eigen::Vector2d& centre_W,
                                     const Eigen::Vector2d& half_m) const {
  const Eigen::Vector2d low = world_->geometry.origin_W;
  const Eigen::Vector2d high = low + world_->geometry.Extent();
  if (((centre_W - half_m).array() < low.array()).any() ||
      ((centre_W + half_m).array() > high.array()).any()) {
    return false;
  }
  for (const Eigen::Vector2d& c : keep_clear_W_) {
    // distance from the disc centre to the nearest point of the rectangle
    const Eigen::Vector2d nearest = c.cwiseMax(centre_W - half_m).cwiseMin(centre_W + half_m);
    if ((c - nearest).norm() < keep_clear_radius_m_) return false;
  }
  return true;
}

Eigen::Vector2d ObstaclePlacer::RandomPosition(common::Random* random, double margin_m) const {
  const Eigen::Vector2d low = world_->geometry.origin_W.array() + margin_m;
  const Eigen::Vector2d high =
      (world_->geometry.origin_W + world_->geometry.Extent()).array() - margin_m;
  return Eigen::Vector2d(random->Uniform(low.x(), high.x()), random->Uniform(low.y(), high.y()));
}

double ObstaclePlacer::MinGroundHeight(const Eigen::Vector2d& p_W, double radius_m) const {
  double lowest = world_->GroundHeight(p_W);
  for (int k = 0; k < 8; ++k) {
    const double angle = k * M_PI / 4.0;
    const Eigen::Vector2d rim = p_W + radius_m * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    lowest = std::min(lowest, world_->GroundHeight(rim));
  }
  return lowest;
}

void ObstaclePlacer::Add(const std::string& kind, Obstacle obstacle) {
  auto it = std::find_if(counts_.begin(), counts_.end(),
                         [&](const auto& entry) { return entry.first == kind; });
  if (it == counts_.end()) it = counts_.insert(counts_.end(), {kind, 0});
  obstacle.name = kind + "_" + std::to_string(it->second++);
  world_->obstacles.push_back(std::move(obstacle));
}

void ObstaclePlacer::AddWall(const Eigen::Vector2d& a_W, const Eigen::Vector2d& b_W,
                             double height_m, double thickness_m,
                             std::vector<std::array<double, 2>> openings,
                             const Eigen::Vector4f& rgba) {
  const double length = (b_W - a_W).norm();
  if (length <= 0.0) return;
  const Eigen::Vector2d direction = (b_W - a_W) / length;
  // keep-clear discs that the wall passes through become openings
  for (const Eigen::Vector2d& c : keep_clear_W_) {
    const double along = (c - a_W).dot(direction);
    const double across = std::abs(direction.x() * (c - a_W).y() - direction.y() * (c - a_W).x());
    const double reach = keep_clear_radius_m_ + thickness_m;
    if (across < reach) {
      const double half = std::sqrt(reach * reach - across * across);
      openings.push_back({along - half, along + half});
    }
  }
  std::sort(openings.begin(), openings.end());
  // the solid pieces are the complement of the openings on [0, length]
  double begin = 0.0;
  auto add_piece = [&](double from, double to) {
    if (to - from < 0.05) return;
    const Eigen::Vector2d mid = a_W + 0.5 * (from + to) * direction;
    const double ground = MinGroundHeight(mid, 0.5 * (to - from));
    Obstacle wall;
    wall.shape = ShapeType::kBox;
    wall.size = Eigen::Vector3d(0.5 * (to - from), 0.5 * thickness_m, 0.5 * height_m + 0.1);
    wall.X_WO = PoseAt(Eigen::Vector3d(mid.x(), mid.y(), ground - 0.2 + wall.size.z()),
                       std::atan2(direction.y(), direction.x()));
    wall.rgba = rgba;
    Add("wall", wall);
  };
  for (const auto& opening : openings) {
    add_piece(begin, std::clamp(opening[0], 0.0, length));
    begin = std::max(begin, std::clamp(opening[1], 0.0, length));
  }
  add_piece(begin, length);
}

}  // namespace internal

TerrainStatistics ComputeStatistics(const TerrainWorld& world) {
  TerrainStatistics stats;
  std::vector<double> slopes = SlopeMagnitudes(world);
  auto to_deg = [](double slope) { return std::atan(slope) / kDegToRad; };
  stats.slope_p50_deg = to_deg(Percentile(slopes, 0.5));
  stats.slope_p95_deg = to_deg(Percentile(slopes, 0.95));
  stats.slope_max_deg =
      to_deg(slopes.empty() ? 0.0 : *std::max_element(slopes.begin(), slopes.end()));
  stats.height_min_m = world.height_m.minCoeff();
  stats.height_max_m = world.height_m.maxCoeff();
  for (const Obstacle& obstacle : world.obstacles) {
    if (obstacle.role == ObstacleRole::kSolid) ++stats.num_obstacles;
    if (obstacle.name.rfind("tree", 0) == 0 && obstacle.role == ObstacleRole::kSolid) {
      ++stats.num_trees;
    }
  }
  const Eigen::Vector2d extent = world.geometry.Extent();
  stats.tree_density_per_m2 = stats.num_trees / (extent.x() * extent.y());
  return stats;
}

}  // namespace trav::sim
