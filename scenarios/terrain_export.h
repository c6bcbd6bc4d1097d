#pragma once

#include "scenarios/output_folder.h"
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
/// - `terrain.json`: grid geometry, height range, statistics and the obstacle list.
void ExportTerrain(const sim::TerrainWorld& world, const OutputFolder& folder);

}  // namespace trav::scenarios
