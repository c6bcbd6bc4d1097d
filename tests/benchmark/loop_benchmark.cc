// The closed loop's real-time factor: the suite's hilly scenario (30 m traverse with LiDAR,
// FSGP-BGK mapping, planning and MPC) for 8 s of simulated time, without video (budget 3x real
// time or more) and with 640 x 480 or 1280 x 720 video through OSMesa (0.5x or more). One run per
// benchmark; the time includes terrain generation, world and BVH building and writing the outputs,
// as in `trav run`. Counters: real_time_factor (simulated / wall seconds of RunScenario) and the
// share of that wall time spent in each module (share_lidar, share_mapping, share_planning,
// share_control, share_physics, share_render) as summary.json's "compute" measures it, with
// share_other for the rest (terrain, world, metrics, video encoding, files; with the mapper on
// its own thread the shares overlap and share_other is what is left); and each module's cost
// inside the loop, to hold against its own benchmark (README): lidar_ms_per_frame (a 20,000-ray
// MID-360 frame, cast over 50 physics steps; lidar_benchmark's BM_EmulatorFrame),
// mapping_ms_median (one FSGP-BGK update; mapping_benchmark's BM_FsgpBgk), control_ms_median (one
// MPC solve; controller_benchmark), planning_ms_median (one replan; planner_benchmark) and
// physics_ms_per_step. BM_ClosedLoopNoVideo/threads:2 maps on a second thread (`trav run
// --threads 2`, the same run bit for bit), threads:1 keeps everything on one.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

#include <benchmark/benchmark.h>

#include "common/enum_names.h"
#include "common/yaml_reader.h"
#include "renders/renderer.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace {

namespace fs = std::filesystem;
using trav::scenarios::RunSummary;
using trav::scenarios::Scenario;

constexpr char kScenarioFile[] = "/scenarios/suite/hilly.yaml";
constexpr double kDuration_s = 8.0;

// A fresh folder for one run's outputs, removed with the object.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& name)
      : path_(fs::temp_directory_path() /
              ("trav_loop_benchmark_" + std::to_string(getpid()) + "_" + name)) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TemporaryFolder() {
    std::error_code error;
    fs::remove_all(path_, error);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  std::string path() const { return path_.string(); }

 private:
  fs::path path_;
};

// A module's times in the summary; all zero when it never ran.
trav::scenarios::ModuleTime TimeOf(const RunSummary& summary, const std::string& module) {
  const auto time = summary.compute.find(module);
  return time == summary.compute.end() ? trav::scenarios::ModuleTime{} : time->second;
}

// A run of the benchmark's scenario; `video_size` (width, height) [pixels], or none; the mapper and
// the ray casting on worker threads, or everything on one thread.
void RunClosedLoop(benchmark::State& state, std::optional<Eigen::Vector2i> video_size,
                   bool worker_threads) {
  const bool video = video_size.has_value();
  Scenario scenario = trav::scenarios::LoadScenario(
      trav::common::YamlDocument::Load(std::string(TRAV_SOURCE_DIR) + kScenarioFile));
  scenario.duration_s = kDuration_s;
  scenario.video.enabled = video;
  if (video) {
    scenario.video.render.width = video_size->x();
    scenario.video.render.height = video_size->y();
  }
  scenario.video.render.backend = trav::renders::GlBackend::kOsmesa;
  const std::string model = trav::scenarios::RobotModelPath(scenario, TRAV_MODELS_DIR);

  RunSummary summary;
  double wall_s = 0.0;
  for (auto _ : state) {
    const TemporaryFolder output(video ? "video" : "no_video");
    const auto start = std::chrono::steady_clock::now();
    trav::scenarios::RunOptions options;
    options.mapping_thread = worker_threads;
    options.lidar_thread = worker_threads;
    summary = trav::scenarios::RunScenario(scenario, model, output.path(), options);
    wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(wall_s);
  }

  state.counters["sim_time_s"] = summary.sim_time_s;
  state.counters["real_time_factor"] = summary.sim_time_s / wall_s;
  state.counters["video_frames"] = summary.video_frames;
  double modules_s = 0.0;
  for (const char* module : trav::scenarios::kTimedModules) {
    const double total_s = TimeOf(summary, module).total_s;
    modules_s += total_s;
    state.counters[std::string("share_") + module] = total_s / wall_s;
  }
  state.counters["share_other"] = 1.0 - modules_s / wall_s;
  if (summary.lidar_frames > 0) {
    state.counters["lidar_ms_per_frame"] =
        1e3 * TimeOf(summary, "lidar").total_s / summary.lidar_frames;
  }
  const trav::scenarios::ModuleTime physics = TimeOf(summary, "physics");
  if (physics.calls > 0)
    state.counters["physics_ms_per_step"] = 1e3 * physics.total_s / physics.calls;
  for (const char* module : {"mapping", "control", "planning"}) {
    state.counters[std::string(module) + "_ms_median"] = TimeOf(summary, module).median_ms;
  }
  state.SetLabel(std::string("outcome ") + trav::common::NameOf(summary.outcome));
}

void BM_ClosedLoopNoVideo(benchmark::State& state) {
  RunClosedLoop(state, std::nullopt, /*worker_threads=*/state.range(0) == 2);
}
BENCHMARK(BM_ClosedLoopNoVideo)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

void BM_ClosedLoopVideo640x480(benchmark::State& state) {
  RunClosedLoop(state, Eigen::Vector2i(640, 480), /*worker_threads=*/true);
}
BENCHMARK(BM_ClosedLoopVideo640x480)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);

void BM_ClosedLoopVideo1280x720(benchmark::State& state) {
  RunClosedLoop(state, Eigen::Vector2i(1280, 720), /*worker_threads=*/true);
}
BENCHMARK(BM_ClosedLoopVideo1280x720)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
