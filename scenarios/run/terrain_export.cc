#include "scenarios/run/terrain_export.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/enum_names.h"
#include "mapping/traversability_mapper.h"
#include "renders/image.h"
#include "renders/overlay.h"
#include "scenarios/run/pcd_io.h"
#include "scenarios/run/scenario_run.h"
#include "sim/terrain_geometry.h"

namespace trav::scenarios {
namespace {

// Sample spacing on obstacle surfaces in the exported cloud, in height-field cells (tree crowns
// and trunks dominate the point count: a forest is about 4 million points at 2 cells).
constexpr double kCloudSpacingCells = 2.0;

void WriteHeightmaps(const sim::TerrainWorld& world, const OutputFolder& folder) {
  const common::GridGeometry& g = world.geometry;
  const float low = world.height_m.minCoeff();
  const float range = std::max(1e-6f, world.height_m.maxCoeff() - low);
  std::vector<std::uint16_t> png(static_cast<std::size_t>(g.num_x) * g.num_y);
  for (int row = 0; row < g.num_y; ++row) {
    const int iy = g.num_y - 1 - row;  // top row = largest y
    for (int ix = 0; ix < g.num_x; ++ix) {
      png[static_cast<std::size_t>(row) * g.num_x + ix] = static_cast<std::uint16_t>(
          std::lround((world.height_m(ix, iy) - low) / range * 65535.0f));
    }
  }
  renders::WritePng16(folder.File("heightmap.png"), g.num_x, g.num_y, png);

  // Eigen's (num_x, num_y) column-major storage is already rows along +y
  std::ofstream raw(folder.File("heightmap.raw"), std::ios::binary);
  raw.write(reinterpret_cast<const char*>(world.height_m.data()),
            static_cast<std::streamsize>(world.height_m.size() * sizeof(float)));
  raw.close();
  CheckWritten(folder.File("heightmap.raw"), !raw.fail());
}

void WriteCloud(const sim::TerrainWorld& world, const OutputFolder& folder) {
  WritePcd(folder.File("cloud.pcd"),
           sim::DenseCloud(world, kCloudSpacingCells * world.geometry.resolution_m));
}

void WritePreview(const sim::TerrainWorld& world, const OutputFolder& folder) {
  const common::GridGeometry& g = world.geometry;
  renders::Image image;
  image.width = g.num_x;
  image.height = g.num_y;
  image.rgb.resize(static_cast<std::size_t>(g.num_x) * g.num_y * 3);
  const float low = world.height_m.minCoeff();
  const float range = std::max(1e-6f, world.height_m.maxCoeff() - low);
  // hill shading: light from the north-west, 45 degrees up; colour from low (green) to high (brown)
  const Eigen::Vector3d light = Eigen::Vector3d(-1, 1, 1.4).normalized();
  for (int row = 0; row < g.num_y; ++row) {
    const int iy = g.num_y - 1 - row;
    for (int ix = 0; ix < g.num_x; ++ix) {
      const int x0 = std::max(ix - 1, 0), x1 = std::min(ix + 1, g.num_x - 1);
      const int y0 = std::max(iy - 1, 0), y1 = std::min(iy + 1, g.num_y - 1);
      const double gx =
          (world.height_m(x1, iy) - world.height_m(x0, iy)) / ((x1 - x0) * g.resolution_m);
      const double gy =
          (world.height_m(ix, y1) - world.height_m(ix, y0)) / ((y1 - y0) * g.resolution_m);
      const double shade =
          std::clamp(Eigen::Vector3d(-gx, -gy, 1).normalized().dot(light), 0.2, 1.0);
      const double t = (world.height_m(ix, iy) - low) / range;
      const Eigen::Vector3d base =
          (1 - t) * Eigen::Vector3d(0.45, 0.62, 0.35) + t * Eigen::Vector3d(0.72, 0.6, 0.45);
      std::uint8_t* pixel = image.rgb.data() + 3 * (static_cast<std::size_t>(row) * g.num_x + ix);
      for (int c = 0; c < 3; ++c)
        pixel[c] = static_cast<std::uint8_t>(std::lround(255 * shade * base[c]));
    }
  }
  // obstacles seen from above, lowest first so canopies cover trunks (the ceiling is left out)
  std::vector<const sim::Obstacle*> order;
  for (const sim::Obstacle& obstacle : world.obstacles) {
    if (obstacle.role != sim::ObstacleRole::kCeiling) order.push_back(&obstacle);
  }
  std::stable_sort(order.begin(), order.end(), [](const sim::Obstacle* a, const sim::Obstacle* b) {
    return a->X_WO.translation().z() < b->X_WO.translation().z();
  });
  for (const sim::Obstacle* obstacle : order) {
    const common::PointCloud surface =
        common::SampleSurface(common::PrimitiveMesh(*obstacle), 0.5 * g.resolution_m);
    for (Eigen::Index i = 0; i < surface.size(); ++i) {
      const auto cell = g.CellIndex(surface.points.col(i).head<2>().cast<double>());
      if (!cell) continue;
      std::uint8_t* pixel =
          image.rgb.data() +
          3 * (static_cast<std::size_t>(g.num_y - 1 - cell->y()) * g.num_x + cell->x());
      for (int c = 0; c < 3; ++c)
        pixel[c] = static_cast<std::uint8_t>(std::lround(255 * obstacle->rgba[c]));
    }
  }
  renders::WritePng(folder.File("preview.png"), image);
}

// Writes a cost layer as <stem>.raw (float32, x fastest) and <stem>.png.
void WriteCostLayer(const Eigen::MatrixXf& cost, const std::string& stem,
                    const OutputFolder& folder) {
  const std::string raw_path = folder.File(stem + ".raw");
  std::ofstream raw(raw_path, std::ios::binary);
  raw.write(reinterpret_cast<const char*>(cost.data()),
            static_cast<std::streamsize>(cost.size() * sizeof(float)));
  raw.close();
  CheckWritten(raw_path, !raw.fail());
  renders::WritePng(folder.File(stem + ".png"), renders::TraversabilityImage(cost));
}

// Writes both ground truths (docs/ground-truth.md): the geometric one as ground_truth.*, the
// physical one as physical_truth.*.
common::GridGeometry WriteGroundTruth(const sim::TerrainWorld& world,
                                      const mapping::FsgpConfig& score,
                                      const mapping::GroundTruthConfig& config,
                                      const OutputFolder& folder) {
  const common::GridGeometry map_geometry = common::GridGeometry::Centered(
      world.geometry.Center(), world.geometry.Extent(), score.area.resolution_m);
  const common::GridLayers geometric = mapping::ComputeGroundTruth(
      map_geometry, world.geometry, world.height_m, sim::ObstacleHeightGrid(world), score, config);
  WriteCostLayer(geometric.Layer(mapping::layers::kTraversability), "ground_truth", folder);
  const common::GridLayers physical = WorldPhysicalTruth(map_geometry, world, config);
  WriteCostLayer(physical.Layer(mapping::layers::kTraversability), "physical_truth", folder);
  return map_geometry;
}

void WriteMetadata(const sim::TerrainWorld& world, const common::GridGeometry& truth_geometry,
                   const OutputFolder& folder) {
  const sim::TerrainStatistics stats = sim::ComputeStatistics(world);
  const common::GridGeometry& g = world.geometry;
  nlohmann::json json;
  json["type"] = common::NameOf(world.config.type);
  json["seed"] = world.config.seed;
  json["grid"] = {{"origin", {g.origin_W.x(), g.origin_W.y()}},
                  {"resolution_m", g.resolution_m},
                  {"num_x", g.num_x},
                  {"num_y", g.num_y}};
  json["ground_truth_grid"] = {
      {"origin", {truth_geometry.origin_W.x(), truth_geometry.origin_W.y()}},
      {"resolution_m", truth_geometry.resolution_m},
      {"num_x", truth_geometry.num_x},
      {"num_y", truth_geometry.num_y}};
  json["height_min_m"] = world.height_m.minCoeff();
  json["height_max_m"] = world.height_m.maxCoeff();
  json["statistics"] = {
      {"slope_p50_deg", stats.slope_p50_deg}, {"slope_p95_deg", stats.slope_p95_deg},
      {"slope_max_deg", stats.slope_max_deg}, {"num_obstacles", stats.num_obstacles},
      {"num_trees", stats.num_trees},         {"tree_density_per_m2", stats.tree_density_per_m2}};
  nlohmann::json obstacles = nlohmann::json::array();
  for (const sim::Obstacle& obstacle : world.obstacles) {
    const Eigen::Vector3d p = obstacle.X_WO.translation();
    const Eigen::Quaterniond q(obstacle.X_WO.linear());
    obstacles.push_back({{"name", obstacle.name},
                         {"position", {p.x(), p.y(), p.z()}},
                         {"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}},
                         {"size", {obstacle.size.x(), obstacle.size.y(), obstacle.size.z()}}});
  }
  json["obstacles"] = obstacles;
  WriteTextFile(folder.File("terrain.json"), json.dump(2) + "\n");
}

}  // namespace

void ExportTerrain(const sim::TerrainWorld& world, const mapping::FsgpConfig& score,
                   const mapping::GroundTruthConfig& ground_truth, const OutputFolder& folder) {
  WriteHeightmaps(world, folder);
  WriteCloud(world, folder);
  WritePreview(world, folder);
  WriteMetadata(world, WriteGroundTruth(world, score, ground_truth, folder), folder);
}

TerrainExportSummary ExportScenarioTerrain(const Scenario& scenario, const OutputFolder& folder) {
  const sim::TerrainWorld world =
      sim::GenerateTerrain(scenario.terrain, {scenario.start_W.position, scenario.goal_W});
  ExportTerrain(world, scenario.mapping, scenario.ground_truth, folder);
  return {common::NameOf(scenario.terrain.type), world.geometry.num_x, world.geometry.num_y,
          world.obstacles.size()};
}

}  // namespace trav::scenarios
