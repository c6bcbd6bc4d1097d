#pragma once

#include <cstddef>
#include <string>

#include "mapping/fsgp_config.h"
#include "mapping/ground_truth.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/scenario.h"
#include "sim/terrain.h"

namespace trav::scenarios {

/// Writes a generated world into `folder` (what `trav terrain` produces):
/// - `heightmap.png`: 16-bit grayscale, white = high, top row = largest y (MuJoCo's PNG
/// height-field
///   convention), heights mapped linearly from height_min_m to height_max_m of terrain.json;
/// - `heightmap.raw`: float32 heights [m], little-endian, row-major with rows along +y starting at
///   the smallest y (num_y rows of num_x values);
/// - `cloud.pcd`: the dense noise-free point cloud (PCL binary PCD, frame W);
/// - `preview.png`: a shaded top view with obstacles in their colours (+y up);
/// - `ground_truth.png` and `ground_truth.raw`: the geometric ground-truth traversability, and
///   `physical_truth.png` and `physical_truth.raw` the physical one (the robot resting on the world
///   at its best heading; docs/ground-truth.md), both on the mapper's grid
///   (`score.area.resolution_m`), colours green (0) to red (1), and float32 values with rows along
///   +y (its grid in terrain.json; NaN where the robot would stand partly off the world);
/// - `terrain.json`: grid geometry, height range, statistics and the obstacle list.
void ExportTerrain(const sim::TerrainWorld& world, const mapping::FsgpConfig& score,
                   const mapping::GroundTruthConfig& ground_truth, const OutputFolder& folder);

/// What ExportScenarioTerrain wrote.
struct TerrainExportSummary {
  std::string terrain_type;  ///< as named in scenario files
  int num_x{0};              ///< height samples along x
  int num_y{0};              ///< and along y
  std::size_t obstacles{0};
};

/// Generates the scenario's world for its start and goal and exports it into `folder`
/// (ExportTerrain with the scenario's mapping and ground-truth settings).
TerrainExportSummary ExportScenarioTerrain(const Scenario& scenario, const OutputFolder& folder);

}  // namespace trav::scenarios
