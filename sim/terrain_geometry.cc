#include "sim/terrain_geometry.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

namespace trav::sim {

TriangleMesh GroundMesh(const TerrainWorld& world) {
  const common::GridGeometry& g = world.geometry;
  TriangleMesh mesh;
  mesh.vertices.resize(3, static_cast<Eigen::Index>(g.num_x) * g.num_y);
  for (int iy = 0; iy < g.num_y; ++iy) {
    for (int ix = 0; ix < g.num_x; ++ix) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      mesh.vertices.col(ix + iy * g.num_x) = Eigen::Vector3f(
          static_cast<float>(p.x()), static_cast<float>(p.y()), world.height_m(ix, iy));
    }
  }
  mesh.triangles.resize(3, 2 * static_cast<Eigen::Index>(g.num_x - 1) * (g.num_y - 1));
  Eigen::Index t = 0;
  for (int iy = 0; iy + 1 < g.num_y; ++iy) {
    for (int ix = 0; ix + 1 < g.num_x; ++ix) {
      const int a = ix + iy * g.num_x;
      const int b = a + 1;
      const int c = a + g.num_x + 1;
      const int d = a + g.num_x;
      mesh.triangles.col(t++) = Eigen::Vector3i(a, b, c);
      mesh.triangles.col(t++) = Eigen::Vector3i(a, c, d);
    }
  }
  return mesh;
}

TriangleMesh ObstacleMesh(const std::vector<Obstacle>& obstacles, int segments) {
  TriangleMesh mesh;
  for (const Obstacle& obstacle : obstacles)
    common::AppendMesh(common::PrimitiveMesh(obstacle, segments), &mesh);
  return mesh;
}

common::PointCloud DenseCloud(const TerrainWorld& world, double spacing_m) {
  std::vector<Eigen::Vector3f> points;
  const common::GridGeometry& g = world.geometry;
  points.reserve(static_cast<std::size_t>(g.num_x) * g.num_y);
  for (int iy = 0; iy < g.num_y; ++iy) {
    for (int ix = 0; ix < g.num_x; ++ix) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                          world.height_m(ix, iy));
    }
  }
  // obstacle surfaces above the ground
  const common::PointCloud surface =
      common::SampleSurface(ObstacleMesh(world.obstacles, 32), spacing_m);
  for (Eigen::Index i = 0; i < surface.size(); ++i) {
    const Eigen::Vector3f p = surface.points.col(i);
    if (p.z() >= world.GroundHeight(p.head<2>().cast<double>()) - 1e-3) points.push_back(p);
  }
  return common::MakePointCloud(points, "W");
}

Eigen::MatrixXf ObstacleHeightGrid(const TerrainWorld& world, double max_height_m) {
  const common::GridGeometry& g = world.geometry;
  Eigen::MatrixXf heights = Eigen::MatrixXf::Zero(g.num_x, g.num_y);
  for (const Obstacle& obstacle : world.obstacles) {
    if (obstacle.role != ObstacleRole::kSolid) continue;
    const common::TriangleMesh mesh = common::PrimitiveMesh(obstacle, 32);
    // the highest ground under the mesh's cells bounds every sample's height above its own cell:
    // samples higher than max_height_m above it (most of a tree's trunk) are skipped before the
    // cell lookup, which changes no cell (float subtraction is monotone)
    const Eigen::Vector3f low = mesh.vertices.rowwise().minCoeff();
    const Eigen::Vector3f high = mesh.vertices.rowwise().maxCoeff();
    // (one cell more on each side: a sample may round a hair outside its triangle)
    const Eigen::Vector2i first =
        g.NearestLatticeIndex(low.head<2>().cast<double>()) - Eigen::Vector2i::Ones();
    const Eigen::Vector2i last =
        g.NearestLatticeIndex(high.head<2>().cast<double>()) + Eigen::Vector2i::Ones();
    const int x0 = std::max(0, first.x()), x1 = std::min(g.num_x - 1, last.x());
    const int y0 = std::max(0, first.y()), y1 = std::min(g.num_y - 1, last.y());
    if (x0 > x1 || y0 > y1) continue;  // wholly off the grid
    const float highest_ground = world.height_m.block(x0, y0, x1 - x0 + 1, y1 - y0 + 1).maxCoeff();
    common::ForEachSurfaceSample(mesh, 0.5 * g.resolution_m, [&](const Eigen::Vector3f& p) {
      if (p.z() - highest_ground > max_height_m) return;
      const std::optional<Eigen::Vector2i> cell = g.CellIndex(p.head<2>().cast<double>());
      if (!cell) return;
      const float above = p.z() - world.height_m(cell->x(), cell->y());
      if (above > 0.0f && above <= max_height_m) {
        heights(cell->x(), cell->y()) = std::max(heights(cell->x(), cell->y()), above);
      }
    });
  }
  return heights;
}

ObstacleRaster ObstacleBandRaster(const TerrainWorld& world, double band_m, double resolution_m) {
  ObstacleRaster raster{common::GridGeometry::Centered(world.geometry.Center(),
                                                       world.geometry.Extent(), resolution_m),
                        {}};
  const common::GridGeometry& g = raster.geometry;
  raster.top_m = Eigen::MatrixXf::Constant(g.num_x, g.num_y, std::nanf(""));
  for (const Obstacle& obstacle : world.obstacles) {
    if (obstacle.role != ObstacleRole::kSolid) continue;
    // the cells under the shape's bounding box
    const Eigen::Vector3d& size = obstacle.size;
    Eigen::Vector3d half = Eigen::Vector3d::Zero();
    switch (obstacle.shape) {
      case ShapeType::kBox:
        half = size;
        break;
      case ShapeType::kSphere:
        half = Eigen::Vector3d::Constant(size[0]);
        break;
      case ShapeType::kCylinder:
        half = Eigen::Vector3d(size[0], size[0], size[1]);
        break;
      case ShapeType::kCapsule:
        half = Eigen::Vector3d(size[0], size[0], size[1] + size[0]);
        break;
    }
    const Eigen::Vector2d reach = (obstacle.X_WO.linear().cwiseAbs() * half).head<2>();
    const Eigen::Vector2d centre = obstacle.X_WO.translation().head<2>();
    const Eigen::Vector2d low = (centre - reach - g.origin_W) / g.resolution_m;
    const Eigen::Vector2d high = (centre + reach - g.origin_W) / g.resolution_m;
    const int x0 = std::max(0, static_cast<int>(std::floor(low.x())));
    const int y0 = std::max(0, static_cast<int>(std::floor(low.y())));
    const int x1 = std::min(g.num_x - 1, static_cast<int>(std::ceil(high.x())));
    const int y1 = std::min(g.num_y - 1, static_cast<int>(std::ceil(high.y())));
    for (int ix = x0; ix <= x1; ++ix) {
      for (int iy = y0; iy <= y1; ++iy) {
        const Eigen::Vector2d p = g.CellCenter(ix, iy);
        const std::optional<std::pair<double, double>> extent = common::VerticalExtent(obstacle, p);
        if (!extent) continue;
        const double ground = common::InterpolateBilinear(world.geometry, world.height_m, p);
        if (extent->second <= ground || extent->first >= ground + band_m) continue;
        const auto top = static_cast<float>(std::min(extent->second, ground + band_m));
        // fmax: NaN (none yet) gives way to a number
        raster.top_m(ix, iy) = std::fmax(raster.top_m(ix, iy), top);
      }
    }
  }
  return raster;
}

lidar::RaySceneDescription RaySceneOf(const TerrainWorld& world,
                                      const std::vector<MovingObstacle>& movers) {
  lidar::RaySceneDescription description;
  description.meshes_W.push_back(GroundMesh(world));
  description.reflectance.push_back(GroundReflectance(world.config.type));
  description.primitives_W.assign(world.obstacles.begin(), world.obstacles.end());
  for (const Obstacle& obstacle : world.obstacles) {
    description.reflectance.push_back(ObstacleReflectance(obstacle.name));
  }
  for (const MovingObstacle& mover : movers) {
    description.moving_meshes_I.push_back(
        common::PrimitiveMesh(MoverPrimitive(mover), description.primitive_segments));
    description.X_WI.push_back(MoverPoseAt(mover, 0.0, world));
    description.reflectance.push_back(MoverReflectance(mover));
  }
  return description;
}

float GroundReflectance(TerrainType type) {
  switch (type) {
    case TerrainType::kHilly:
    case TerrainType::kSlope:
    case TerrainType::kHeightmap:
    case TerrainType::kMesh:
      return 0.5f;
    case TerrainType::kForest:
      return 0.25f;
    case TerrainType::kRuin:
      return 0.3f;
    case TerrainType::kRoad:
      return 0.12f;
    case TerrainType::kIndoor:
      return 0.4f;
    case TerrainType::kFlat:
    case TerrainType::kStep:
    case TerrainType::kStairs:
      return 0.35f;
  }
  return lidar::kDefaultReflectance;
}

float ObstacleReflectance(const std::string& name) {
  // the kind is the name's prefix ("tree_3", "placed_box_1" keeps the placed object's kind)
  struct Kind {
    const char* prefix;
    float reflectance;
  };
  static constexpr Kind kKinds[] = {
      {"tree", 0.35f},   {"canopy", 0.5f},     {"box", 0.35f},   {"riser", 0.35f},
      {"column", 0.35f}, {"rubble", 0.3f},     {"wall", 0.7f},   {"ceiling", 0.8f},
      {"pole", 0.45f},   {"furniture", 0.45f}, {"table", 0.45f},
  };
  const std::string kind = name.rfind("placed_", 0) == 0 ? name.substr(7) : name;
  for (const Kind& k : kKinds) {
    if (kind.rfind(k.prefix, 0) == 0) return k.reflectance;
  }
  return lidar::kDefaultReflectance;
}

float MoverReflectance(const MovingObstacle& mover) {
  return mover.shape == MoverShape::kCapsule ? 0.35f : 0.45f;
}

}  // namespace trav::sim
