// One map update on a 20,000-point MID-360 frame (emulated with sim/lidar over 100 ms of driving)
// of a hilly and of a forest terrain: FSGP-BGK with its stage times, and SGP and the elevation map
// on the same frame. Budget: FSGP-BGK median 10 ms or less on one core (the paper: 33.84 ms with an
// RTX 4060). BM_FsgpBgkSequence checks that memory stays flat over a long run.
#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include "mapping/baselines.h"
#include "mapping/fsgp_bgk_mapper.h"
#include "mapping/ground_truth.h"
#include "mapping/lidar_odometry.h"
#include "mapping/physical_truth.h"
#include "sim/lidar/lidar_emulator.h"
#include "sim/terrain_geometry.h"

namespace {

using trav::lidar::LidarFrame;

struct Frames {
  std::vector<trav::common::PointCloud> clouds_W;
  std::vector<Eigen::Isometry3d> poses_W;
  std::vector<trav::common::PointCloud> scans_L;  // as the sensor reports them, for the odometry
  std::vector<Eigen::Isometry3d> X_WL_end;
};

// Frames of the robot driving at 1 m/s along +x from (-10, 0), 0.3 m above the ground.
const Frames& MakeFrames(trav::sim::TerrainType type, int count) {
  static std::map<std::pair<int, int>, Frames> cache;
  Frames& frames = cache[{static_cast<int>(type), count}];
  if (!frames.clouds_W.empty()) return frames;
  trav::sim::TerrainConfig config;
  config.type = type;
  config.seed = 7;
  const trav::sim::TerrainWorld world = trav::sim::GenerateTerrain(config, {{-10.0, 0.0}});
  const trav::lidar::RayScene scene(trav::sim::RaySceneOf(world));
  trav::lidar::LidarEmulator lidar{trav::lidar::LidarConfig{}};
  LidarFrame frame;
  double t = 0.0;
  while (static_cast<int>(frames.clouds_W.size()) < count) {
    const Eigen::Vector2d xy(-10.0 + t, 0.0);
    Eigen::Isometry3d X_WL = Eigen::Isometry3d::Identity();
    X_WL.translation() = Eigen::Vector3d(xy.x(), xy.y(), world.GroundHeight(xy) + 0.3);
    lidar.Scan(scene, t, t + 0.002, X_WL);
    t += 0.002;
    if (!lidar.frame_ready()) continue;
    lidar.TakeFrame(&frame);
    frames.clouds_W.push_back(trav::common::PointCloud{
        trav::lidar::PointsInWorld(frame), {}, {}, {}, {}, frame.points_L.stamp_s, "W"});
    Eigen::Isometry3d X_WB = frame.X_WL_end;
    X_WB.translation().z() -= 0.2;
    frames.poses_W.push_back(X_WB);
    frames.scans_L.push_back(frame.points_L);
    frames.X_WL_end.push_back(frame.X_WL_end);
  }
  return frames;
}

void Report(benchmark::State& state, const std::vector<trav::mapping::MapUpdateResult>& results) {
  trav::mapping::StageTimes sum;
  for (const auto& r : results) {
    sum.crop += r.times.crop;
    sum.features += r.times.features;
    sum.fit += r.times.fit;
    sum.predict += r.times.predict;
    sum.fusion += r.times.fusion;
    sum.smoothing += r.times.smoothing;
  }
  const double n = static_cast<double>(results.size());
  state.counters["crop_ms"] = sum.crop / n;
  state.counters["features_ms"] = sum.features / n;
  state.counters["fit_ms"] = sum.fit / n;
  state.counters["predict_ms"] = sum.predict / n;
  state.counters["fusion_ms"] = sum.fusion / n;
  state.counters["smoothing_ms"] = sum.smoothing / n;
  state.counters["training_points"] = results.back().training_points;
  state.counters["cells"] = results.back().observed_cells;
}

template <typename MakeMapper>
void RunMapper(benchmark::State& state, MakeMapper make) {
  const auto type = static_cast<trav::sim::TerrainType>(state.range(0));
  const Frames& frames = MakeFrames(type, 20);
  auto mapper = make();
  std::vector<trav::mapping::MapUpdateResult> results;
  std::size_t k = 0;
  for (auto _ : state) {
    results.push_back(
        mapper->Update(frames.clouds_W[k], frames.poses_W[k], 0.1 * static_cast<double>(k)));
    k = (k + 1) % frames.clouds_W.size();
  }
  Report(state, results);
  state.SetLabel(trav::common::NameOf(type));
}

void BM_FsgpBgk(benchmark::State& state) {
  RunMapper(state, [] {
    return std::make_unique<trav::mapping::FsgpBgkMapper>(trav::mapping::FsgpConfig{});
  });
}
// The same without the drop test (`mapping.drop_gap` 0), to measure its share side by side.
void BM_FsgpBgkWithoutDrops(benchmark::State& state) {
  RunMapper(state, [] {
    trav::mapping::FsgpConfig config;
    config.area.drop_gap_m = 0.0;
    return std::make_unique<trav::mapping::FsgpBgkMapper>(config);
  });
}
void BM_Sgp(benchmark::State& state) {
  RunMapper(state,
            [] { return std::make_unique<trav::mapping::SgpMapper>(trav::mapping::SgpConfig{}); });
}
void BM_ElevationMap(benchmark::State& state) {
  RunMapper(state, [] {
    return std::make_unique<trav::mapping::ElevationMapper>(trav::mapping::ElevationMapConfig{},
                                                            trav::mapping::FsgpConfig{});
  });
}
constexpr int kHilly = static_cast<int>(trav::sim::TerrainType::kHilly);
constexpr int kForest = static_cast<int>(trav::sim::TerrainType::kForest);
BENCHMARK(BM_FsgpBgk)->Arg(kHilly)->Arg(kForest)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FsgpBgkWithoutDrops)
    ->Arg(kHilly)
    ->Arg(kForest)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Sgp)->Arg(kHilly)->Arg(kForest)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ElevationMap)->Arg(kHilly)->Arg(kForest)->Unit(benchmark::kMillisecond)->UseRealTime();

// The three methods on the same 20 frames, timed here so the ratios print in one row.
void BM_Ratios(benchmark::State& state) {
  const auto type = static_cast<trav::sim::TerrainType>(state.range(0));
  const Frames& frames = MakeFrames(type, 20);
  auto time_mapper = [&](trav::mapping::TraversabilityMapper* mapper) {
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t k = 0; k < frames.clouds_W.size(); ++k)
      mapper->Update(frames.clouds_W[k], frames.poses_W[k], 0.1 * k);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
               .count() /
           static_cast<double>(frames.clouds_W.size());
  };
  for (auto _ : state) {
    trav::mapping::FsgpBgkMapper fsgp{trav::mapping::FsgpConfig{}};
    trav::mapping::SgpMapper sgp{trav::mapping::SgpConfig{}};
    trav::mapping::ElevationMapper em{trav::mapping::ElevationMapConfig{},
                                      trav::mapping::FsgpConfig{}};
    const double fsgp_ms = time_mapper(&fsgp);
    state.counters["fsgp_bgk_ms"] = fsgp_ms;
    state.counters["sgp_over_fsgp_bgk"] = time_mapper(&sgp) / fsgp_ms;
    state.counters["em_over_fsgp_bgk"] = time_mapper(&em) / fsgp_ms;
  }
  state.SetLabel(trav::common::NameOf(type));
}
BENCHMARK(BM_Ratios)->Arg(kHilly)->Arg(kForest)->Unit(benchmark::kMillisecond)->Iterations(1);

long PeakRssKb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

// 200 frames driving 20 m: the peak memory grows by the map's fixed size only.
void BM_FsgpBgkSequence(benchmark::State& state) {
  const Frames& frames = MakeFrames(static_cast<trav::sim::TerrainType>(kHilly), 200);
  for (auto _ : state) {
    trav::mapping::FsgpBgkMapper mapper{trav::mapping::FsgpConfig{}};
    for (std::size_t k = 0; k < 20; ++k)
      mapper.Update(frames.clouds_W[k], frames.poses_W[k], 0.1 * k);
    const long after_20 = PeakRssKb();
    for (std::size_t k = 20; k < frames.clouds_W.size(); ++k)
      mapper.Update(frames.clouds_W[k], frames.poses_W[k], 0.1 * k);
    state.counters["peak_rss_growth_kb_after_frame_20"] =
        static_cast<double>(PeakRssKb() - after_20);
  }
}
BENCHMARK(BM_FsgpBgkSequence)->Unit(benchmark::kMillisecond)->Iterations(1);

// The LiDAR odometry (localization.method scan-matching, no gyroscope): 30 scans of driving through
// the forest at 1 m/s, each de-skewed, thinned and registered against the local map (time per
// scan: the iteration's time / 30, or 1 / items_per_second); the final position error beside.
void BM_LidarOdometryScan(benchmark::State& state) {
  const Frames& frames = MakeFrames(trav::sim::TerrainType::kForest, 30);
  double error_m = 0.0;
  for (auto _ : state) {
    trav::mapping::LidarOdometry odometry(trav::mapping::LidarOdometryConfig{},
                                          frames.X_WL_end.front());
    for (const trav::common::PointCloud& scan : frames.scans_L) {
      benchmark::DoNotOptimize(odometry.AddScan(scan.points, scan.time_offsets, 0.1));
    }
    error_m = (odometry.X_OL().translation() - frames.X_WL_end.back().translation()).norm();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(frames.scans_L.size()));
  state.counters["final_error_m"] = error_m;
}
BENCHMARK(BM_LidarOdometryScan)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

namespace {

// The two ground truths of a 50 x 50 m forest on the 0.2 m map (docs/ground-truth.md), each with
// the obstacle grid it reads: the geometric one (the score formula over 0.3 m neighbourhoods) and
// the physical one (the robot resting at 16 headings on a 2.5 cm obstacle outline). CPU time.
const trav::sim::TerrainWorld& TruthWorld() {
  static const trav::sim::TerrainWorld world = [] {
    trav::sim::TerrainConfig config;
    config.type = trav::sim::TerrainType::kForest;
    config.seed = 7;
    return trav::sim::GenerateTerrain(config);
  }();
  return world;
}

trav::common::GridGeometry TruthMap(const trav::sim::TerrainWorld& world) {
  return trav::common::GridGeometry::Centered(world.geometry.Center(), world.geometry.Extent(),
                                              0.2);
}

void BM_GeometricTruth(benchmark::State& state) {
  const trav::sim::TerrainWorld& world = TruthWorld();
  for (auto _ : state) {
    const trav::common::GridLayers truth = trav::mapping::ComputeGroundTruth(
        TruthMap(world), world.geometry, world.height_m, trav::sim::ObstacleHeightGrid(world),
        trav::mapping::FsgpConfig{}, trav::mapping::GroundTruthConfig{});
    benchmark::DoNotOptimize(truth.geometry().num_x);
  }
}
BENCHMARK(BM_GeometricTruth)->Unit(benchmark::kMillisecond);

void BM_PhysicalTruth(benchmark::State& state) {
  const trav::sim::TerrainWorld& world = TruthWorld();
  for (auto _ : state) {
    const trav::sim::ObstacleRaster obstacles = trav::sim::ObstacleBandRaster(
        world, trav::mapping::RestingBody{}.height_m, trav::mapping::kObstacleOutlineResolution_m);
    const trav::common::GridLayers truth = trav::mapping::ComputePhysicalTruth(
        TruthMap(world),
        trav::mapping::RestingSurface{world.geometry, world.height_m, obstacles.geometry,
                                      obstacles.top_m},
        trav::mapping::RestingBody{}, trav::mapping::GroundTruthConfig{});
    benchmark::DoNotOptimize(truth.geometry().num_x);
  }
}
BENCHMARK(BM_PhysicalTruth)->Unit(benchmark::kMillisecond);

}  // namespace
