// Ray casting for the MID-360 emulation on a 50 x 50 m hilly terrain at 0.1 m (500,000 triangles)
// with 200 obstacles. Budget: a 20,000-ray frame in 2 ms or less on one core. BM_MujocoRay casts
// the same rays with MuJoCo's mj_ray for comparison (ratio = its time / BM_EmbreeFrame's);
// BM_EmbreeForestFrame casts them in the default forest, among trunks and crowns.
#include <chrono>
#include <cstring>
#include <string>

#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include "sim/lidar/lidar_emulator.h"
#include "sim/lidar/scan_pattern.h"
#include "sim/simulation.h"
#include "sim/terrain_geometry.h"

namespace {

using trav::lidar::RayHits;
using trav::lidar::RayScene;

// The benchmark world: hilly 50 x 50 m with 200 boxes and cylinders placed around the sensor.
const trav::sim::TerrainWorld& World() {
  static const trav::sim::TerrainWorld world = [] {
    trav::sim::TerrainConfig config;
    config.type = trav::sim::TerrainType::kRuin;
    config.seed = 7;
    config.ruin.num_boxes = 80;
    config.ruin.num_columns = 60;
    config.ruin.num_walls = 0;
    config.ruin.num_rubble = 60;
    return trav::sim::GenerateTerrain(config);
  }();
  return world;
}

const RayScene& Scene() {
  static const RayScene scene(trav::sim::RaySceneOf(World()));
  return scene;
}

// One frame of MID-360 directions (the default pattern, Livox's table), in W for a level sensor.
Eigen::Matrix3Xf FrameDirections() {
  const auto pattern = trav::lidar::TablePattern::Mid360();
  Eigen::Matrix3Xf directions(3, 20000);
  for (int i = 0; i < 20000; ++i) directions.col(i) = pattern->Ray(i).direction_L;
  return directions;
}

// A level sensor 0.3 m above the ground at the centre of `world`.
Eigen::Vector3f SensorOrigin(const trav::sim::TerrainWorld& world) {
  return Eigen::Vector3f(0.0f, 0.0f, static_cast<float>(world.GroundHeight({0.0, 0.0})) + 0.3f);
}

// Casts one frame of directions from SensorOrigin(world) per iteration on `threads` threads.
void CastFrames(benchmark::State& state, const RayScene& scene,
                const trav::sim::TerrainWorld& world, int threads) {
  const Eigen::Matrix3Xf directions = FrameDirections();
  const Eigen::Vector3f origin = SensorOrigin(world);
  RayHits hits;
  for (auto _ : state) {
    scene.Cast(origin, directions, 40.0f, &hits, threads);
    benchmark::DoNotOptimize(hits.range_m.data());
  }
  state.SetItemsProcessed(state.iterations() * directions.cols());
  state.counters["hit_fraction"] = (hits.object_id.array() >= 0).cast<double>().mean();
}

void BM_EmbreeFrame(benchmark::State& state) {
  CastFrames(state, Scene(), World(), static_cast<int>(state.range(0)));
}
BENCHMARK(BM_EmbreeFrame)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same frame in the default forest (50 x 50 m, 0.08 trees per m^2: 200 trunks and their
// crowns, spheres of 1 to 2.4 m whose undersides most rays from below meet), from 0.3 m above the
// ground at the centre.
void BM_EmbreeForestFrame(benchmark::State& state) {
  static const trav::sim::TerrainWorld forest = [] {
    trav::sim::TerrainConfig config;
    config.type = trav::sim::TerrainType::kForest;
    config.seed = 101;
    return trav::sim::GenerateTerrain(config);
  }();
  static const RayScene scene(trav::sim::RaySceneOf(forest));
  CastFrames(state, scene, forest, 1);
}
BENCHMARK(BM_EmbreeForestFrame)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_EmulatorFrame(benchmark::State& state) {
  const RayScene& scene = Scene();
  trav::lidar::LidarEmulator lidar{trav::lidar::LidarConfig{}};
  trav::lidar::LidarFrame frame;
  Eigen::Isometry3d X_WL = Eigen::Isometry3d::Identity();
  X_WL.translation() = SensorOrigin(World()).cast<double>();
  double t = 0.0;
  for (auto _ : state) {
    // one frame in 50 physics steps of 2 ms, as in a run
    for (int step = 0; step < 50; ++step, t += 0.002) lidar.Scan(scene, t, t + 0.002, X_WL);
    lidar.TakeFrame(&frame);
    benchmark::DoNotOptimize(frame.points_L.points.data());
  }
  state.SetItemsProcessed(state.iterations() * lidar.rays_per_frame());
}
BENCHMARK(BM_EmulatorFrame)->Unit(benchmark::kMillisecond)->UseRealTime();

// The directions of one frame, as the emulator asks for them (Rays, 400 at a time): the procedural
// model (BM_PatternFrame) and Livox's table (BM_TablePatternFrame).
void PatternFrames(const trav::lidar::ScanPattern& pattern, benchmark::State& state) {
  Eigen::Matrix3Xf directions(3, 400);
  Eigen::VectorXi lines(400);
  std::int64_t index = 0;
  for (auto _ : state) {
    for (int batch = 0; batch < 50; ++batch, index += 400) {
      pattern.Rays(index, 400, &directions, &lines);
      benchmark::DoNotOptimize(directions.data());
    }
  }
  state.SetItemsProcessed(state.iterations() * 20000);
}

void BM_PatternFrame(benchmark::State& state) {
  PatternFrames(trav::lidar::ProceduralMid360Pattern(), state);
}
BENCHMARK(BM_PatternFrame)->Unit(benchmark::kMillisecond);

void BM_TablePatternFrame(benchmark::State& state) {
  PatternFrames(*trav::lidar::TablePattern::Mid360(), state);
}
BENCHMARK(BM_TablePatternFrame)->Unit(benchmark::kMillisecond);

void BM_MujocoRay(benchmark::State& state) {
  const RayScene& scene = Scene();  // built before any timing
  trav::sim::WorldOptions options;
  options.robot_model_path = std::string(TRAV_MODELS_DIR) + "/scout_mini.xml";
  trav::sim::Simulation simulation(World(), trav::common::Pose2{}, options);
  const Eigen::Matrix3Xf directions = FrameDirections();
  const int rays = static_cast<int>(state.range(0));
  const Eigen::Vector3f origin = SensorOrigin(World());
  const mjtNum p[3] = {origin.x(), origin.y(), origin.z()};
  // geom groups 0-2 and 4 (obstacles, ceiling) and 3 (the collision ground); the robot sits far
  // away
  const mjtByte groups[6] = {1, 1, 1, 1, 1, 0};
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    for (int i = 0; i < rays; ++i) {
      const mjtNum v[3] = {directions(0, i), directions(1, i), directions(2, i)};
      int geom = -1;
      benchmark::DoNotOptimize(
          mj_ray(simulation.model(), simulation.data(), p, v, groups, 1, -1, &geom));
    }
  }
  state.SetItemsProcessed(state.iterations() * rays);
  state.SetLabel("rays per iteration: " + std::to_string(rays) + " (a frame is 20,000)");

  // the same rays with Embree on one thread, timed here for the ratio
  const auto mujoco_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RayHits hits;
  const auto embree_start = std::chrono::steady_clock::now();
  for (benchmark::IterationCount k = 0; k < state.iterations(); ++k) {
    scene.Cast(origin, directions.leftCols(rays), 40.0f, &hits);
  }
  const auto embree_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - embree_start).count();
  state.counters["embree_speedup"] = mujoco_s / embree_s;
}
BENCHMARK(BM_MujocoRay)->Arg(2000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
