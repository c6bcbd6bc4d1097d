// Milliseconds per rendered frame of the robot on a 50 x 50 m hilly terrain, chase camera.
// One GL backend per process (MuJoCo's GL loader binds the first one it finds), chosen with
// --backend=osmesa|egl: run the program once per backend.
#include <cstring>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "renders/renderer.h"
#include "sim/simulation.h"

namespace {

using trav::renders::GlBackend;

GlBackend g_backend = GlBackend::kOsmesa;

void BM_RenderFrame(benchmark::State& state) {
  trav::sim::TerrainConfig terrain;
  terrain.type = trav::sim::TerrainType::kHilly;
  terrain.seed = 7;
  const trav::sim::TerrainWorld world = trav::sim::GenerateTerrain(terrain);
  trav::sim::WorldOptions options;
  options.robot_model_path = std::string(TRAV_MODELS_DIR) + "/scout_mini.xml";
  trav::sim::Simulation simulation(world, trav::common::Pose2{}, options);
  for (int i = 0; i < 200; ++i) simulation.Step();

  trav::renders::RenderConfig config;
  config.width = static_cast<int>(state.range(0));
  config.height = static_cast<int>(state.range(1));
  config.backend = g_backend;
  config.shadows = state.range(2) != 0;
  static std::unique_ptr<trav::renders::Renderer> renderer;  // one GL context per process
  renderer.reset();
  renderer = std::make_unique<trav::renders::Renderer>(&simulation, config);
  trav::renders::ChaseCamera camera;
  trav::renders::Image image;
  for (auto _ : state) {
    renderer->Render(simulation, camera.Update(simulation.State().X_WB, 1.0 / 30.0), {}, &image);
    benchmark::DoNotOptimize(image.rgb.data());
  }
  renderer.reset();
  state.SetLabel(trav::common::NameOf(g_backend));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RenderFrame)
    ->ArgNames({"width", "height", "shadows"})
    ->Args({640, 480, 0})
    ->Args({1280, 720, 0})
    ->Args({640, 480, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--backend=egl") == 0) g_backend = GlBackend::kEgl;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
