// trav run: one scenario into its output folder.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>

#include "common/enum_names.h"
#include "common/input_error.h"
#include "scenarios/cli/cli.h"
#include "scenarios/run/mcap_recorder.h"

namespace trav::scenarios::cli {
namespace {

struct RunFlags {
  ScenarioOptions scenario;
  std::optional<bool> video;
  std::optional<bool> mcap;
  bool record_clouds{false};
  int threads{2};
};

// Fakes the failure a scenario asks for (test_fault): a crash, or a run that never ends. A test
// hook, so only where the environment enables it (TRAV_TEST_FAULTS=1, docs/reliability.md).
void InjectFault(TestFault fault) {
  if (fault == TestFault::kNone) return;
  const char* enabled = std::getenv("TRAV_TEST_FAULTS");
  if (enabled == nullptr || std::string(enabled) != "1") {
    throw common::InputError("test_fault", "",
                             "is a test hook; it works only with TRAV_TEST_FAULTS=1 in the "
                             "environment");
  }
  if (fault == TestFault::kCrash) std::abort();
  while (fault == TestFault::kHang) pause();
}

int Run(const RunFlags& flags) {
  const Scenario scenario = ResolveScenario(flags.scenario, flags.video, flags.mcap);
  InjectFault(scenario.test_fault);
  RunOptions run_options;
  run_options.record_clouds = flags.record_clouds;
  run_options.mapping_thread = flags.threads > 1;
  run_options.lidar_thread = flags.threads > 1;
  const RunSummary summary = RunInFolder(scenario, run_options, flags.scenario.overwrite);
  const std::string& out = scenario.output_dir;

  std::printf("outcome: %s (expected %s)\n", common::NameOf(summary.outcome),
              common::NameOf(scenario.expected_outcome));
  std::printf("simulated %.1f s in %.1f s wall time (%.1fx real time), drove %.1f m\n",
              summary.sim_time_s, summary.wall_time_s, summary.real_time_factor,
              summary.distance_m);
  if (summary.lidar_frames > 0) {
    std::printf("lidar: %d frames, %.0f points and %.2f ms of ray casting per frame%s\n",
                summary.lidar_frames, summary.lidar_points_per_frame, summary.lidar_ms_per_frame,
                flags.record_clouds ? " (clouds/*.pcd)" : "");
  }
  std::printf("summary: %s/summary.json\n", out.c_str());
  if (summary.video_frames > 0) {
    std::printf("video:   %s/video.mp4 (%d frames)\n", out.c_str(), summary.video_frames);
  }
  if (summary.mcap) std::printf("mcap:    %s/%s (Foxglove)\n", out.c_str(), kMcapFileName);
  return summary.outcome == scenario.expected_outcome ? kExitExpected : kExitOtherOutcome;
}

}  // namespace

Command AddRunCommand(CLI::App* app) {
  auto flags = std::make_shared<RunFlags>();
  CLI::App* run = app->add_subcommand("run",
                                      "Run a scenario and write summary.json, trajectory.csv "
                                      "and video.mp4 into its output folder");
  AddScenarioOptions(run, &flags->scenario);
  run->add_flag_callback(
      "--video", [flags] { flags->video = true; }, "Record video.mp4 (overrides video.enabled)");
  run->add_flag_callback(
      "--no-video", [flags] { flags->video = false; }, "Do not record a video");
  run->add_flag_callback(
      "--mcap", [flags] { flags->mcap = true; },
      "Write run.mcap for Foxglove (overrides output.mcap, docs/foxglove.md)");
  run->add_flag_callback(
      "--no-mcap", [flags] { flags->mcap = false; }, "Do not write run.mcap");
  run->add_flag("--record-clouds", flags->record_clouds,
                "Write every LiDAR frame as clouds/frame_NNNNNN.pcd");
  run->add_option("--threads", flags->threads,
                  "1: everything on one thread; 2: both cores, the rays cast and the mapper "
                  "(when navigation.mapping_latency is at least a physics step) on worker "
                  "threads (the same run, bit for bit, docs/performance.md)")
      ->check(CLI::Range(1, 2))
      ->capture_default_str();
  return {run, [flags] { return Run(*flags); }};
}

}  // namespace trav::scenarios::cli
