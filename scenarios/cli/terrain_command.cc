// trav terrain: a scenario's world exported as heightmap, point cloud, preview and ground truth.
#include <cstdio>
#include <memory>

#include "common/input_error.h"
#include "scenarios/cli/cli.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/terrain_export.h"

namespace trav::scenarios::cli {
namespace {

int Terrain(const ScenarioOptions& options) {
  ScenarioOptions terrain_options = options;
  if (!terrain_options.out) throw common::InputError("--out", "", "trav terrain needs --out DIR");
  const Scenario scenario = ResolveScenario(terrain_options, std::nullopt);
  OutputFolder folder(scenario.output_dir, "terrain", options.overwrite);
  const TerrainExportSummary written = ExportScenarioTerrain(scenario, folder);
  folder.Commit();
  std::printf("terrain %s (seed %llu): %d x %d samples, %zu obstacles\n",
              written.terrain_type.c_str(), static_cast<unsigned long long>(scenario.terrain.seed),
              written.num_x, written.num_y, written.obstacles);
  std::printf(
      "written to %s (heightmap.png, heightmap.raw, cloud.pcd, preview.png, ground_truth.png, "
      "ground_truth.raw, physical_truth.png, physical_truth.raw, terrain.json)\n",
      folder.final_path().c_str());
  return kExitExpected;
}

}  // namespace

Command AddTerrainCommand(CLI::App* app) {
  auto options = std::make_shared<ScenarioOptions>();
  CLI::App* terrain = app->add_subcommand(
      "terrain", "Generate a scenario's terrain and export heightmap, point cloud and preview");
  AddScenarioOptions(terrain, options.get());
  return {terrain, [options] { return Terrain(*options); }};
}

}  // namespace trav::scenarios::cli
