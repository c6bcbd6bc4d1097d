// Real-time factor of the Scout Mini driving on a 50 x 50 m hilly terrain (budget: >= 50x).
#include <string>

#include <benchmark/benchmark.h>

#include "controller/skid_steer.h"
#include "sim/simulation.h"

namespace {

void BM_DriveOnHillyTerrain(benchmark::State& state) {
  trav::sim::TerrainConfig terrain;
  terrain.type = trav::sim::TerrainType::kHilly;
  terrain.seed = 7;
  terrain.resolution_m = static_cast<double>(state.range(0)) / 100.0;
  const trav::sim::TerrainWorld world = trav::sim::GenerateTerrain(terrain);
  trav::sim::WorldOptions options;
  options.robot_model_path = std::string(TRAV_MODELS_DIR) + "/scout_mini.xml";
  trav::sim::Simulation simulation(world, trav::common::Pose2{}, options);
  const trav::controller::SkidSteerConfig skid_steer;
  // a gentle curve at 1.5 m/s keeps the robot on the terrain for the whole measurement
  simulation.SetWheelSpeedCommands(trav::controller::ToWheelSpeeds({1.5, 0.1}, skid_steer));
  constexpr int kStepsPerIteration = 500;  // one simulated second
  for (auto _ : state) {
    for (int i = 0; i < kStepsPerIteration; ++i) simulation.Step();
  }
  const double simulated_s = state.iterations() * kStepsPerIteration * simulation.timestep();
  state.counters["real_time_factor"] = benchmark::Counter(simulated_s, benchmark::Counter::kIsRate);
  state.counters["sim_seconds"] = simulated_s;
}
BENCHMARK(BM_DriveOnHillyTerrain)
    ->ArgName("resolution_cm")
    ->Arg(10)
    ->Arg(5)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(3.0);

void BM_GenerateTerrain(benchmark::State& state) {
  trav::sim::TerrainConfig terrain;
  terrain.type = static_cast<trav::sim::TerrainType>(state.range(0));
  for (auto _ : state) {
    benchmark::DoNotOptimize(trav::sim::GenerateTerrain(terrain).height_m.data());
  }
  state.SetLabel(trav::common::NameOf(terrain.type));
}
BENCHMARK(BM_GenerateTerrain)
    ->DenseRange(static_cast<int>(trav::sim::TerrainType::kHilly),
                 static_cast<int>(trav::sim::TerrainType::kIndoor))
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
