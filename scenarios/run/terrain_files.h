#pragma once

#include <string>

#include "sim/terrain.h"

namespace trav::scenarios {

/// Reads the file of `terrain.parameters.file` for the terrain types that take ground from a file
/// (heightmap, mesh; nothing for the others). A relative path is taken from the folder of the
/// scenario file `scenario_source` (the working directory for a scenario without a file, "<built-in
/// default>") and replaced by the absolute path, so that the resolved scenario.yaml replays from
/// anywhere. @throws common::InputError naming the scenario file, the key and the value.
void LoadTerrainFiles(const std::string& scenario_source, sim::TerrainConfig* terrain);

/// Heightmap: a grayscale PNG mapped linearly onto `height_range`, or a float32 `.raw` of
/// `samples` heights, into `heightmap->heights_m`.
void LoadHeightmapFile(const std::string& scenario_source, sim::HeightmapParams* heightmap);

/// Mesh: an OBJ, STL or PLY file (read with PCL's VTK-based reader; polygons split into triangle
/// fans) into `mesh->mesh_W`.
void LoadGroundMeshFile(const std::string& scenario_source, sim::MeshGroundParams* mesh);

}  // namespace trav::scenarios
