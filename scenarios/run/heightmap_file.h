#pragma once

#include <string>

#include "sim/terrain.h"

namespace trav::scenarios {

/// Reads the file of `terrain.parameters.file` (terrain type heightmap) into
/// `heightmap->heights_m`: a grayscale PNG mapped linearly onto `height_range`, or a float32 `.raw`
/// of `samples` heights. A relative path is taken from the folder of the scenario file
/// `scenario_source` (the working directory for a scenario without a file, "<built-in default>")
/// and replaced by the absolute path, so that the resolved scenario.yaml replays from anywhere.
/// @throws common::InputError naming the scenario file, the key and the value.
void LoadHeightmapFile(const std::string& scenario_source, sim::HeightmapParams* heightmap);

}  // namespace trav::scenarios
