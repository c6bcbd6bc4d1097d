// Scene generators for the paper's terrain classes (its section V).
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "sim/terrain_internal.h"

namespace trav::sim::internal {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
// Clear gap kept between tree trunks so the 0.58 m wide robot can pass between most of them [m].
constexpr double kTreeGap_m = 1.0;

const Eigen::Vector4f kBark(0.40f, 0.28f, 0.18f, 1.0f);
const Eigen::Vector4f kLeaves(0.20f, 0.45f, 0.18f, 1.0f);
const Eigen::Vector4f kStone(0.55f, 0.53f, 0.50f, 1.0f);
const Eigen::Vector4f kConcrete(0.70f, 0.70f, 0.68f, 1.0f);
const Eigen::Vector4f kBuilding(0.62f, 0.55f, 0.48f, 1.0f);
const Eigen::Vector4f kPole(0.30f, 0.30f, 0.32f, 1.0f);
const Eigen::Vector4f kWall(0.85f, 0.83f, 0.78f, 1.0f);
const Eigen::Vector4f kFurniture(0.50f, 0.35f, 0.22f, 1.0f);

Obstacle MakeObstacle(ShapeType shape, const Eigen::Isometry3d& X_WO, const Eigen::Vector3d& size,
                      const Eigen::Vector4f& rgba, ObstacleRole role = ObstacleRole::kSolid) {
  Obstacle obstacle;
  obstacle.shape = shape;
  obstacle.role = role;
  obstacle.X_WO = X_WO;
  obstacle.size = size;
  obstacle.rgba = rgba;
  return obstacle;
}

// A vertical cylinder standing on the ground at p_W, its base sunk `sink_m` below the lowest ground
// under it, reaching `height_m` above the ground at its centre.
Obstacle StandingCylinder(const ObstaclePlacer& placer, const Eigen::Vector2d& p_W, double radius_m,
                          double height_m, double sink_m, const Eigen::Vector4f& rgba) {
  const double base = placer.MinGroundHeight(p_W, radius_m) - sink_m;
  const double top = placer.world().GroundHeight(p_W) + height_m;
  const double half = 0.5 * (top - base);
  return MakeObstacle(ShapeType::kCylinder,
                      PoseAt(Eigen::Vector3d(p_W.x(), p_W.y(), base + half), 0.0),
                      Eigen::Vector3d(radius_m, half, 0.0), rgba);
}

}  // namespace

void GenerateForest(const TerrainConfig& config, common::Random* random, ObstaclePlacer* placer) {
  FillHillyGround(config, random, &placer->world());
  const ForestParams& params = config.forest;
  const Eigen::Vector2d extent = placer->world().geometry.Extent();
  const int target =
      static_cast<int>(std::lround(params.tree_density_per_m2 * extent.x() * extent.y()));

  // dart throwing with a minimum clear gap between trunks (a Poisson-disk set)
  std::vector<std::pair<Eigen::Vector2d, double>> trunks;
  for (int attempt = 0; attempt < 50 * target && static_cast<int>(trunks.size()) < target;
       ++attempt) {
    const double radius = random->Uniform(params.trunk_radius_m[0], params.trunk_radius_m[1]);
    const Eigen::Vector2d p = placer->RandomPosition(random, radius);
    if (!placer->IsFree(p, radius)) continue;
    const bool clear = std::all_of(trunks.begin(), trunks.end(), [&](const auto& other) {
      return (other.first - p).norm() >= other.second + radius + kTreeGap_m;
    });
    if (!clear) continue;
    trunks.emplace_back(p, radius);
    const double height = random->Uniform(params.trunk_height_m[0], params.trunk_height_m[1]);
    placer->Add("tree", StandingCylinder(*placer, p, radius, height, 0.2, kBark));
    if (params.canopy) {
      // the crown: a sphere centred near the top of the trunk, seen but not collided with
      const double crown = std::clamp(0.3 * height, 1.0, 2.5);
      const double z = placer->world().GroundHeight(p) + height;
      placer->Add("canopy",
                  MakeObstacle(ShapeType::kSphere, PoseAt(Eigen::Vector3d(p.x(), p.y(), z), 0.0),
                               Eigen::Vector3d(crown, 0.0, 0.0), kLeaves, ObstacleRole::kCanopy));
    }
  }
}

void GenerateRuin(const TerrainConfig& config, common::Random* random, ObstaclePlacer* placer) {
  FillHillyGround(config, random, &placer->world());
  const RuinParams& params = config.ruin;
  TerrainWorld& world = placer->world();

  // tilted boxes, partly buried
  for (int placed = 0, attempt = 0;
       placed < params.num_boxes && attempt < 100 * (params.num_boxes + 1); ++attempt) {
    const Eigen::Vector3d half(random->Uniform(0.1, 1.0), random->Uniform(0.1, 1.0),
                               random->Uniform(0.1, 1.0));
    const Eigen::Vector2d p = placer->RandomPosition(random, 1.0);
    // the 3-D half diagonal bounds the footprint of the tilted box
    if (!placer->IsFree(p, half.norm())) continue;
    const double burial = random->Uniform(0.0, params.burial_fraction_max);
    const double z = world.GroundHeight(p) + half.z() * (1.0 - 2.0 * burial);
    const double tilt = random->Uniform(-20.0, 20.0) * kDegToRad;
    placer->Add("box", MakeObstacle(ShapeType::kBox,
                                    PoseAt(Eigen::Vector3d(p.x(), p.y(), z),
                                           random->Uniform(0, 2 * M_PI), tilt),
                                    half, kStone));
    ++placed;
  }
  // columns: about a third have fallen and lie on the ground
  for (int placed = 0, attempt = 0;
       placed < params.num_columns && attempt < 100 * (params.num_columns + 1); ++attempt) {
    const double radius = random->Uniform(0.15, 0.4);
    const double length = random->Uniform(0.5, 3.0);
    const Eigen::Vector2d p = placer->RandomPosition(random, 2.0);
    const bool fallen = random->Bernoulli(0.35);
    if (!placer->IsFree(p, fallen ? 0.5 * length + radius : radius)) continue;
    if (fallen) {
      const double z = world.GroundHeight(p) + 0.7 * radius;
      Eigen::Isometry3d X = PoseAt(Eigen::Vector3d(p.x(), p.y(), z), random->Uniform(0, 2 * M_PI));
      X.linear() =
          X.linear() * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
      placer->Add("column", MakeObstacle(ShapeType::kCylinder, X,
                                         Eigen::Vector3d(radius, 0.5 * length, 0.0), kStone));
    } else {
      placer->Add("column", StandingCylinder(*placer, p, radius, length, 0.2, kStone));
    }
    ++placed;
  }
  // low walls with one gap each
  for (int placed = 0, attempt = 0;
       placed < params.num_walls && attempt < 100 * (params.num_walls + 1); ++attempt) {
    const double length = random->Uniform(2.0, 6.0);
    const Eigen::Vector2d centre = placer->RandomPosition(random, 0.5 * length + 0.5);
    const double yaw = random->Uniform(0, M_PI);
    const Eigen::Vector2d half = 0.5 * length * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
    const double gap_start = random->Uniform(0.2, std::max(0.3, length - 1.4));
    placer->AddWall(centre - half, centre + half, random->Uniform(0.3, 1.5),
                    random->Uniform(0.2, 0.3), {{gap_start, gap_start + random->Uniform(1.0, 1.5)}},
                    kStone);
    ++placed;
  }
  // rubble: small boxes the robot can drive over (115 mm clearance)
  for (int placed = 0, attempt = 0;
       placed < params.num_rubble && attempt < 100 * (params.num_rubble + 1); ++attempt) {
    const Eigen::Vector3d half(random->Uniform(0.05, 0.2), random->Uniform(0.05, 0.2),
                               random->Uniform(0.025, 0.075));
    const Eigen::Vector2d p = placer->RandomPosition(random, 0.5);
    if (!placer->IsFree(p, half.norm())) continue;
    placer->Add(
        "rubble",
        MakeObstacle(ShapeType::kBox,
                     PoseAt(Eigen::Vector3d(p.x(), p.y(), world.GroundHeight(p) + 0.5 * half.z()),
                            random->Uniform(0, 2 * M_PI), random->Uniform(-10.0, 10.0) * kDegToRad),
                     half, kStone));
    ++placed;
  }
}

void GenerateRoad(const TerrainConfig& config, common::Random* random, ObstaclePlacer* placer) {
  const RoadParams& params = config.road;
  TerrainWorld& world = placer->world();
  const double half_street = 0.5 * params.street_width_m;
  const double sidewalk_end = half_street + params.sidewalk_width_m;
  // distance from a coordinate to the nearest street centre line (streets at multiples of the
  // block)
  auto street_offset = [&](double u) {
    return std::abs(u - params.block_size_m * std::round(u / params.block_size_m));
  };
  for (int iy = 0; iy < world.geometry.num_y; ++iy) {
    for (int ix = 0; ix < world.geometry.num_x; ++ix) {
      const Eigen::Vector2d p = world.geometry.CellCenter(ix, iy);
      const double dx = street_offset(p.x());
      const double dy = street_offset(p.y());
      const double d = std::min(dx, dy);
      // road with a crown on its centre line (camber), sidewalks raised by the curb height
      const double h = d < half_street ? params.camber * (half_street - d) : params.curb_height_m;
      world.height_m(ix, iy) = static_cast<float>(h);
    }
  }
  // buildings fill the block interiors; poles stand on the sidewalks
  const Eigen::Vector2d low = world.geometry.origin_W;
  const Eigen::Vector2d high = low + world.geometry.Extent();
  const int kx0 = static_cast<int>(std::floor(low.x() / params.block_size_m));
  const int ky0 = static_cast<int>(std::floor(low.y() / params.block_size_m));
  for (int kx = kx0; kx * params.block_size_m < high.x(); ++kx) {
    for (int ky = ky0; ky * params.block_size_m < high.y(); ++ky) {
      const Eigen::Vector2d block_low =
          Eigen::Vector2d(kx, ky) * params.block_size_m + Eigen::Vector2d::Constant(sidewalk_end);
      const Eigen::Vector2d block_high = Eigen::Vector2d(kx + 1, ky + 1) * params.block_size_m -
                                         Eigen::Vector2d::Constant(sidewalk_end);
      // one or two buildings per block, set back from the sidewalk by a random margin
      const int num_buildings = 1 + static_cast<int>(random->UniformIndex(2));
      const double span = block_high.x() - block_low.x();
      for (int b = 0; b < num_buildings; ++b) {
        const double x0 = block_low.x() + span * b / num_buildings + random->Uniform(0.3, 1.5);
        const double x1 =
            block_low.x() + span * (b + 1) / num_buildings - random->Uniform(0.3, 1.5);
        const double y0 = block_low.y() + random->Uniform(0.3, 1.5);
        const double y1 = block_high.y() - random->Uniform(0.3, 1.5);
        const Eigen::Vector2d centre(0.5 * (x0 + x1), 0.5 * (y0 + y1));
        const Eigen::Vector2d half(0.5 * (x1 - x0), 0.5 * (y1 - y0));
        if (half.minCoeff() < 0.5 || !placer->IsRectangleFree(centre, half)) continue;
        const double height = random->Uniform(5.0, 20.0);
        placer->Add(
            "building",
            MakeObstacle(ShapeType::kBox,
                         PoseAt(Eigen::Vector3d(centre.x(), centre.y(), 0.5 * height - 0.2), 0.0),
                         Eigen::Vector3d(half.x(), half.y(), 0.5 * height + 0.2), kBuilding));
      }
      for (int k = 0; k < params.poles_per_block; ++k) {
        // on the sidewalk along the block's lower x edge or lower y edge
        const double along = random->Uniform(0.0, params.block_size_m);
        const double across = half_street + random->Uniform(0.3, params.sidewalk_width_m - 0.3);
        const Eigen::Vector2d corner = Eigen::Vector2d(kx, ky) * params.block_size_m;
        const Eigen::Vector2d p = random->Bernoulli(0.5) ? corner + Eigen::Vector2d(along, across)
                                                         : corner + Eigen::Vector2d(across, along);
        const double radius = random->Uniform(0.05, 0.12);
        if (!placer->IsFree(p, radius)) continue;
        placer->Add("pole",
                    StandingCylinder(*placer, p, radius, random->Uniform(3.0, 6.0), 0.2, kPole));
      }
    }
  }
}

namespace {

struct Room {
  Eigen::Vector2d low;
  Eigen::Vector2d high;
};

// A doorway in an axis-aligned wall: the wall lies at `wall_coordinate` on axis `normal_axis` and
// the opening spans [low, high] along the other axis [m].
struct Doorway {
  int normal_axis;
  double wall_coordinate;
  double low;
  double high;
};

// The distance from p_W to the opening of `doorway` [m].
double DistanceToDoorway(const Eigen::Vector2d& p_W, const Doorway& doorway) {
  const int along = 1 - doorway.normal_axis;
  Eigen::Vector2d nearest;
  nearest[doorway.normal_axis] = doorway.wall_coordinate;
  nearest[along] = std::clamp(p_W[along], doorway.low, doorway.high);
  return (p_W - nearest).norm();
}

// A uniform draw from [low, high] less the `excluded` intervals, or nothing if they cover it. One
// draw of `random` whatever the exclusions, mapped onto what they leave: with none inside
// [low, high] it is random->Uniform(low, high) exactly.
std::optional<double> UniformOutside(double low, double high,
                                     std::vector<std::array<double, 2>> excluded,
                                     common::Random* random) {
  std::sort(excluded.begin(), excluded.end());
  std::vector<std::array<double, 2>> allowed;
  double from = low;
  for (const auto& [a, b] : excluded) {
    if (a > from) allowed.push_back({from, std::min(a, high)});
    from = std::max(from, b);
    if (from >= high) break;
  }
  if (from < high) allowed.push_back({from, high});
  double measure = 0.0;
  for (const auto& [a, b] : allowed) measure += std::max(0.0, b - a);
  const double u = random->Uniform(0.0, measure);
  if (measure <= 0.0) return std::nullopt;
  double left = u;
  for (const auto& [a, b] : allowed) {
    const double length = std::max(0.0, b - a);
    if (left < length) return a + left;
    left -= length;
  }
  return allowed.back()[1];
}

// Splits `room` recursively along its longer side until both sides are below twice the minimum;
// each split adds a wall with a doorway. A wall never ends in a doorway of the room's sides: its
// end stays half its thickness plus kDoorwayApproach_m clear of each one, so every doorway keeps
// its full width and opens onto floor (a room too small for such a wall is not split).
void SplitRoom(const Room& room, const IndoorParams& params, common::Random* random,
               ObstaclePlacer* placer, std::vector<Room>* rooms, std::vector<Doorway>* doorways) {
  constexpr double kDoorwayApproach_m = 0.4;
  const Eigen::Vector2d size = room.high - room.low;
  const int axis = size.x() >= size.y() ? 0 : 1;
  if (size[axis] < 2.0 * params.min_room_size_m) {
    rooms->push_back(room);
    return;
  }
  const int other = 1 - axis;
  // the new wall's ends meet the room's two sides along `axis`
  const double margin = 0.5 * params.wall_thickness_m + kDoorwayApproach_m;
  std::vector<std::array<double, 2>> excluded;
  for (const Doorway& doorway : *doorways) {
    const bool on_side = doorway.normal_axis == other &&
                         (std::abs(doorway.wall_coordinate - room.low[other]) < 1e-9 ||
                          std::abs(doorway.wall_coordinate - room.high[other]) < 1e-9);
    if (on_side) excluded.push_back({doorway.low - margin, doorway.high + margin});
  }
  const std::optional<double> cut =
      UniformOutside(room.low[axis] + params.min_room_size_m,
                     room.high[axis] - params.min_room_size_m, std::move(excluded), random);
  if (!cut) {
    rooms->push_back(room);
    return;
  }
  Eigen::Vector2d a = room.low;
  Eigen::Vector2d b = room.high;
  a[axis] = *cut;
  b[axis] = *cut;
  const double length = size[other];
  const double door = random->Uniform(0.5, length - params.door_width_m - 0.5);
  placer->AddWall(a, b, params.wall_height_m, params.wall_thickness_m,
                  {{door, door + params.door_width_m}}, kWall);
  doorways->push_back(
      {axis, *cut, room.low[other] + door, room.low[other] + door + params.door_width_m});
  Room first = room;
  Room second = room;
  first.high[axis] = *cut;
  second.low[axis] = *cut;
  SplitRoom(first, params, random, placer, rooms, doorways);
  SplitRoom(second, params, random, placer, rooms, doorways);
}

}  // namespace

void GenerateIndoor(const TerrainConfig& config, common::Random* random, ObstaclePlacer* placer) {
  const IndoorParams& params = config.indoor;
  TerrainWorld& world = placer->world();
  const Eigen::Vector2d low = world.geometry.origin_W;
  const Eigen::Vector2d high = low + world.geometry.Extent();

  // outer walls, rooms, a ceiling over everything
  const Eigen::Vector2d corners[4] = {low, {high.x(), low.y()}, high, {low.x(), high.y()}};
  for (int k = 0; k < 4; ++k) {
    placer->AddWall(corners[k], corners[(k + 1) % 4], params.wall_height_m, params.wall_thickness_m,
                    {}, kWall);
  }
  std::vector<Room> rooms;
  std::vector<Doorway> doorways;
  SplitRoom({low, high}, params, random, placer, &rooms, &doorways);
  const Eigen::Vector2d centre = 0.5 * (low + high);
  const Eigen::Vector2d half = 0.5 * (high - low);
  placer->Add("ceiling",
              MakeObstacle(
                  ShapeType::kBox,
                  PoseAt(Eigen::Vector3d(centre.x(), centre.y(), params.wall_height_m + 0.05), 0.0),
                  Eigen::Vector3d(half.x(), half.y(), 0.05), kWall, ObstacleRole::kCeiling));

  // furniture away from the walls and kDoorwayClearance_m clear of every doorway (a piece of at
  // most kFurnitureRadius_m round its centre), so that doorways stay open: boxes and tables with
  // thin legs
  constexpr double kFurnitureRadius_m = 0.85;
  constexpr double kDoorwayClearance_m = 1.0;
  for (const Room& room : rooms) {
    const double inset = 1.2;
    if ((room.high - room.low).minCoeff() < 2.0 * inset + 0.5) continue;
    for (int k = 0; k < params.furniture_per_room; ++k) {
      const Eigen::Vector2d p(random->Uniform(room.low.x() + inset, room.high.x() - inset),
                              random->Uniform(room.low.y() + inset, room.high.y() - inset));
      if (!placer->IsFree(p, 0.9)) continue;
      const bool near_doorway =
          std::any_of(doorways.begin(), doorways.end(), [&](const Doorway& doorway) {
            return DistanceToDoorway(p, doorway) < kFurnitureRadius_m + kDoorwayClearance_m;
          });
      if (near_doorway) continue;
      const double yaw = random->Uniform(0, M_PI);
      if (random->Bernoulli(0.5)) {
        const Eigen::Vector3d box(random->Uniform(0.2, 0.6), random->Uniform(0.2, 0.6),
                                  random->Uniform(0.2, 0.5));
        placer->Add("furniture", MakeObstacle(ShapeType::kBox,
                                              PoseAt(Eigen::Vector3d(p.x(), p.y(), box.z()), yaw),
                                              box, kFurniture));
        continue;
      }
      // table: a top at 0.75 m on four legs of 2.5 cm radius
      const Eigen::Vector3d top(0.6, 0.4, 0.02);
      const Eigen::Isometry3d X_top = PoseAt(Eigen::Vector3d(p.x(), p.y(), 0.75), yaw);
      placer->Add("table", MakeObstacle(ShapeType::kBox, X_top, top, kFurniture));
      for (int leg = 0; leg < 4; ++leg) {
        const Eigen::Vector3d corner_T((leg & 1 ? 1 : -1) * (top.x() - 0.05),
                                       (leg & 2 ? 1 : -1) * (top.y() - 0.05), -0.375);
        const Eigen::Vector3d p_leg = X_top * corner_T;
        placer->Add("table_leg", MakeObstacle(ShapeType::kCylinder, PoseAt(p_leg, 0.0),
                                              Eigen::Vector3d(0.025, 0.375, 0.0), kFurniture));
      }
    }
  }
}

}  // namespace trav::sim::internal
