// A* across a 50 x 50 m traversability map at 0.1 m (501 x 501 cells) with smooth random costs and
// lethal blobs, corner to corner: search costs, A* and path simplification. Budget (with the
// trajectory optimiser, which is not built yet): 50 ms. OMPL's RRT*, BIT* and RRT-Connect on the
// same map, start and goal as baselines, with their cost against A*'s.
#include <cmath>
#include <cstdint>
#include <limits>

#include <benchmark/benchmark.h>

#include "common/random.h"
#include "planner/astar.h"
#include "planner/cost_map.h"
#include "planner/ompl_planner.h"

namespace {

trav::common::GridLayers CostMap() {
  trav::common::GridLayers map(
      trav::common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(50, 50), 0.1),
      {"traversability"});
  trav::common::Random random(3);
  Eigen::MatrixXf& cost = map.Layer("traversability");
  const trav::common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      cost(ix, iy) = static_cast<float>(0.3 + 0.25 * std::sin(0.4 * p.x()) * std::cos(0.3 * p.y()));
    }
  }
  // 150 lethal discs of 0.3 to 1 m
  for (int k = 0; k < 150; ++k) {
    const Eigen::Vector2d c(random.Uniform(-22, 22), random.Uniform(-22, 22));
    const double r = random.Uniform(0.3, 1.0);
    for (int ix = 0; ix < g.num_x; ++ix) {
      for (int iy = 0; iy < g.num_y; ++iy) {
        if ((g.CellCenter(ix, iy) - c).norm() < r) cost(ix, iy) = 1.0f;
      }
    }
  }
  return map;
}

const Eigen::Vector2d kStart(-24, -24);
const Eigen::Vector2d kGoal(24, 24);

void BM_AStarAcrossTheMap(benchmark::State& state) {
  const trav::common::GridLayers map = CostMap();
  const trav::planner::AStarConfig config;
  int expansions = 0;
  std::size_t waypoints = 0;
  for (auto _ : state) {
    const trav::planner::GridPlanner planner(map, config);
    const trav::planner::GridPath path = planner.Plan(kStart, kGoal);
    waypoints = planner.Simplify(path.points_W).size();
    expansions = path.expansions;
    benchmark::DoNotOptimize(path.cost);
  }
  state.counters["expansions"] = expansions;
  state.counters["waypoints"] = static_cast<double>(waypoints);
}
BENCHMARK(BM_AStarAcrossTheMap)->Unit(benchmark::kMillisecond);

// One sampling-based query per iteration with a 0.2 s limit (RRT* and BIT* use all of it,
// RRT-Connect stops at its first path) and the iteration's own seed; the cost map is built once,
// outside the timing. Counters: the share of queries that found a path, their mean cost and its
// ratio to A*'s optimal grid cost (A* once, outside the loop; astar_segment_cost is its path
// measured like the sampling planners' paths, with SegmentCost), and the mean OMPL iterations and
// tree vertices.
void BM_OmplAcrossTheMap(benchmark::State& state, trav::planner::SamplingAlgorithm algorithm) {
  const trav::common::GridLayers map = CostMap();
  const trav::planner::AStarConfig astar_config;
  const trav::planner::GridPath astar =
      trav::planner::GridPlanner(map, astar_config).Plan(kStart, kGoal);
  const trav::planner::SearchCostMap costs(map, astar_config);
  double astar_segment_cost = 0.0;
  for (std::size_t i = 1; i < astar.points_W.size(); ++i) {
    astar_segment_cost += costs.SegmentCost(astar.points_W[i - 1], astar.points_W[i]);
  }
  trav::planner::SamplingPlannerConfig config;
  config.algorithm = algorithm;
  config.time_limit_s = 0.2;
  int found = 0;
  double cost_sum = 0.0, iterations_sum = 0.0, vertices_sum = 0.0;
  std::uint32_t seed = 1;
  for (auto _ : state) {
    config.seed = seed++;
    const trav::planner::SamplingResult result = PlanSampling(costs, config, kStart, kGoal);
    if (result.path.status == trav::planner::PlanStatus::kFound) {
      ++found;
      cost_sum += result.path.cost;
    }
    iterations_sum += result.iterations;
    vertices_sum += result.path.expansions;
  }
  const double queries = static_cast<double>(state.iterations());
  const double cost = found > 0 ? cost_sum / found : std::numeric_limits<double>::quiet_NaN();
  state.counters["found"] = found / queries;
  state.counters["cost"] = cost;
  state.counters["cost_ratio"] = cost / astar.cost;
  state.counters["astar_cost"] = astar.cost;
  state.counters["astar_segment_cost"] = astar_segment_cost;
  state.counters["iterations"] = iterations_sum / queries;
  state.counters["vertices"] = vertices_sum / queries;
}
BENCHMARK_CAPTURE(BM_OmplAcrossTheMap, rrt_star, trav::planner::SamplingAlgorithm::kRrtStar)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
BENCHMARK_CAPTURE(BM_OmplAcrossTheMap, bit_star, trav::planner::SamplingAlgorithm::kBitStar)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
BENCHMARK_CAPTURE(BM_OmplAcrossTheMap, rrt_connect, trav::planner::SamplingAlgorithm::kRrtConnect)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);

}  // namespace

BENCHMARK_MAIN();
