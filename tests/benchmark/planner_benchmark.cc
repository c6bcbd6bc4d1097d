// A* across a 50 x 50 m traversability map at 0.1 m (501 x 501 cells) with smooth random costs and
// lethal blobs, corner to corner: search costs, A* and path simplification. Budget (with the
// trajectory optimiser, which is not built yet): 50 ms.
#include <cmath>

#include <benchmark/benchmark.h>

#include "common/random.h"
#include "planner/astar.h"

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

void BM_AStarAcrossTheMap(benchmark::State& state) {
  const trav::common::GridLayers map = CostMap();
  const trav::planner::AStarConfig config;
  int expansions = 0;
  std::size_t waypoints = 0;
  for (auto _ : state) {
    const trav::planner::GridPlanner planner(map, config);
    const trav::planner::GridPath path = planner.Plan({-24, -24}, {24, 24});
    waypoints = planner.Simplify(path.points_W).size();
    expansions = path.expansions;
    benchmark::DoNotOptimize(path.cost);
  }
  state.counters["expansions"] = expansions;
  state.counters["waypoints"] = static_cast<double>(waypoints);
}
BENCHMARK(BM_AStarAcrossTheMap)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
