// The batch machinery's cost and its parallel speed-up.
// - BM_MachineryPerRun: jobs that do nothing but write their result file (a /bin/sh one-liner)
//   through RunJobsLocally, one at a time: the overhead per run of spawning, waiting and recording
//   (budget: under 50 ms per run).
// - BM_TravBatch16Runs/jobs:1 and /jobs:2: `trav batch` on 16 equal runs (a 4 s MPC tracking run on
//   flat ground each), end to end; jobs:2 reports speedup, its wall time against jobs:1's in the
//   same process.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "scenarios/experiments/job_array.h"

namespace {

namespace fs = std::filesystem;
using trav::scenarios::Job;

fs::path FreshFolder(const std::string& name) {
  const fs::path path =
      fs::temp_directory_path() / ("trav_batch_benchmark_" + std::to_string(getpid()) + "_" + name);
  fs::remove_all(path);
  fs::create_directories(path / "results");
  fs::create_directories(path / "logs");
  return path;
}

void BM_MachineryPerRun(benchmark::State& state) {
  const int runs = static_cast<int>(state.range(0));
  double wall_s = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    const fs::path folder = FreshFolder("machinery");
    std::vector<Job> jobs;
    for (int i = 0; i < runs; ++i) {
      const std::string id = "run" + std::to_string(i);
      const std::string result = (folder / "results" / (id + ".json")).string();
      jobs.push_back({id,
                      {"/bin/sh", "-c", "echo {} > " + result},
                      (folder / "logs" / (id + ".log")).string(),
                      result});
    }
    state.ResumeTiming();
    const auto start = std::chrono::steady_clock::now();
    const trav::scenarios::JobsProgress progress =
        trav::scenarios::RunJobsLocally(folder.string(), jobs, 1, 60.0, nullptr);
    wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.PauseTiming();
    if (progress.finished != runs) state.SkipWithError("a job did not finish");
    fs::remove_all(folder);
    state.ResumeTiming();
  }
  state.counters["ms_per_run"] =
      1e3 * wall_s / (static_cast<double>(runs) * static_cast<double>(state.iterations()));
}
BENCHMARK(BM_MachineryPerRun)->Arg(32)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

double g_one_job_s = 0.0;

void BM_TravBatch16Runs(benchmark::State& state) {
  const int jobs = static_cast<int>(state.range(0));
  const fs::path folder = FreshFolder("trav_" + std::to_string(jobs));
  std::ofstream(folder / "line.yaml")
      << "schema_version: 1\nname: line\nmode: track\nterrain: {type: flat, size: [20, 20]}\n"
         "robot: {start: [-6, 0, 0]}\ntrack: {reference: line, size: 12.0, speed: 1.0}\n"
         "duration: 4\nlidar: {enabled: false}\nvideo: {enabled: false}\n";
  std::ofstream(folder / "batch.yaml")
      << "scenarios: [line.yaml]\nsweep: {seeds: {first: 1, count: 16}}\n";
  double wall_s = 0.0;
  for (auto _ : state) {
    fs::remove_all(folder / "out");
    const auto start = std::chrono::steady_clock::now();
    const std::string command =
        std::string(TRAV_BINARY) + " batch " + (folder / "batch.yaml").string() + " --out " +
        (folder / "out").string() + " --jobs " + std::to_string(jobs) + " > /dev/null 2>&1";
    if (std::system(command.c_str()) != 0) state.SkipWithError("trav batch failed");
    wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  if (jobs == 1) g_one_job_s = wall_s;
  if (jobs > 1 && g_one_job_s > 0.0) state.counters["speedup"] = g_one_job_s / wall_s;
  state.counters["s_per_run"] = wall_s / 16.0;
  fs::remove_all(folder);
}
BENCHMARK(BM_TravBatch16Runs)
    ->ArgName("jobs")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
