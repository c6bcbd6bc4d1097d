// Milliseconds per rendered frame of the robot on a 50 x 50 m hilly terrain, chase camera, as a
// closed loop's video draws it: the view with three LiDAR frames of points (20,000 each), a draped
// 20 x 20 m map at 0.2 m and two walkers, and a map panel of 3/8 of the frame's width.
// One GL backend per process (MuJoCo's GL loader binds the first one it finds), chosen with
// --backend=osmesa|egl: run the program once per backend.
#include <cstring>
#include <memory>
#include <random>
#include <string>

#include <benchmark/benchmark.h>

#include "renders/renderer.h"
#include "sim/simulation.h"

namespace {

using trav::renders::GlBackend;

GlBackend g_backend = GlBackend::kOsmesa;

// What a closed loop's video adds to a frame of `world` at the robot's start (the origin).
trav::renders::Overlay ClosedLoopOverlay(const trav::sim::TerrainWorld& world,
                                         const trav::renders::RenderConfig& config) {
  trav::renders::Overlay overlay;
  std::mt19937 random(1);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  for (int frame = 0; frame < 3; ++frame) {
    trav::renders::ColoredPoints points;
    points.points_W.resize(3, 20000);
    points.rgba = Eigen::Vector4f(0.2f, 0.5f, 1.0f, (frame + 1) / 3.0f);
    for (Eigen::Index i = 0; i < points.points_W.cols(); ++i) {
      const Eigen::Vector2d p(15.0 * uniform(random), 15.0 * uniform(random));
      points.points_W.col(i) = Eigen::Vector3f(p.x(), p.y(), world.GroundHeight(p));
    }
    overlay.points.push_back(std::move(points));
  }
  trav::renders::GroundGrid map;
  map.geometry =
      trav::common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(20, 20), 0.2);
  map.values.resize(map.geometry.num_x, map.geometry.num_y);
  map.heights_m.resize(map.geometry.num_x, map.geometry.num_y);
  for (int iy = 0; iy < map.geometry.num_y; ++iy) {
    for (int ix = 0; ix < map.geometry.num_x; ++ix) {
      map.values(ix, iy) = 0.5f + 0.5f * uniform(random);
      map.heights_m(ix, iy) =
          static_cast<float>(world.GroundHeight(map.geometry.CellCenter(ix, iy)));
    }
  }
  overlay.grids.push_back(std::move(map));
  for (int k = 0; k < 2; ++k) {
    trav::renders::Walker walker;
    const Eigen::Vector2d p(3.0 + k, 1.5 - 3.0 * k);
    walker.X_WO.translation() = Eigen::Vector3d(p.x(), p.y(), world.GroundHeight(p) + 0.85);
    overlay.walkers.push_back(walker);
  }
  overlay.texts.push_back(
      {"t 6.0 s   v 1.00 m/s   goal 24.8 m", trav::renders::TextCorner::kTopLeft});
  overlay.panel.image.width = config.panel_width;
  overlay.panel.image.height = config.height;
  overlay.panel.image.rgb.assign(3 * static_cast<std::size_t>(config.panel_width) * config.height,
                                 90);
  for (int k = 0; k < 12; ++k) {
    overlay.panel.texts.push_back({"legend", Eigen::Vector2i(10, 20 * k), Eigen::Vector3f::Ones()});
  }
  return overlay;
}

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
  config.panel_width = static_cast<int>(0.375 * config.width);
  static std::unique_ptr<trav::renders::Renderer> renderer;  // one GL context per process
  renderer.reset();
  renderer = std::make_unique<trav::renders::Renderer>(&simulation, config);
  trav::renders::ChaseCamera camera;
  trav::renders::Image image;
  const trav::renders::Overlay overlay = ClosedLoopOverlay(world, config);
  for (auto _ : state) {
    renderer->Render(simulation, camera.Update(simulation.State().X_WB, 1.0 / 30.0), overlay,
                     &image);
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
    ->Args({1280, 720, 1})
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
