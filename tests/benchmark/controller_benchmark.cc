// One MPC solve with the default horizon (N = 30, 0.05 s steps) while tracking a figure-eight at
// 1 m/s on a kinematic unicycle, warm-started as in a run. Budget: median 2 ms or less on one core.
// Reports the median and 99th percentile solve times and the mean iterations.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "controller/mpc.h"

namespace {

void BM_MpcSolve(benchmark::State& state) {
  std::vector<Eigen::Vector2d> path;
  for (double a = 0.0; a <= 2.0 * M_PI; a += 0.002)
    path.emplace_back(3.0 * std::sin(a), 3.0 * std::sin(a) * std::cos(a));
  const trav::common::Trajectory reference = trav::common::TrajectoryAlongPath(path, 1.0, 1.0);
  trav::controller::MpcConfig config;
  trav::controller::MpcController mpc(config);
  trav::controller::MpcState robot;
  std::vector<double> times_ms;
  double iterations = 0.0;
  double t = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const trav::controller::MpcResult result = mpc.Solve(robot, reference, t);
    times_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
    iterations += result.iterations;
    // the unicycle follows the command for one control period; the reference loops
    robot.position_W += config.control_period_s * result.command.v *
                        Eigen::Vector2d(std::cos(robot.yaw), std::sin(robot.yaw));
    robot.yaw += config.control_period_s * result.command.omega;
    robot.v = result.command.v;
    robot.omega = result.command.omega;
    t += config.control_period_s;
    if (t > reference.end_time()) {
      t = 0.0;
      robot = trav::controller::MpcState{};
      mpc.Reset();
    }
  }
  std::sort(times_ms.begin(), times_ms.end());
  state.counters["median_ms"] = times_ms[times_ms.size() / 2];
  state.counters["p99_ms"] =
      times_ms[static_cast<std::size_t>(0.99 * static_cast<double>(times_ms.size() - 1))];
  state.counters["iterations"] = iterations / static_cast<double>(times_ms.size());
}
BENCHMARK(BM_MpcSolve)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

}  // namespace

BENCHMARK_MAIN();
