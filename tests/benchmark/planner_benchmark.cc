// A* across a 50 x 50 m traversability map (0.1 m: 501 x 501 cells, and 0.2 m) with smooth random
// costs and lethal blobs, corner to corner, w = 0 and w = 5: search costs, A* and path
// simplification. OMPL's RRT*, BIT* and RRT-Connect on the same map, start and goal as baselines,
// with their cost against A*'s. The planning stack on a 20 m route among 10 obstacles (A*,
// simplification and trajectory optimisation; budget 50 ms), and its replanning 0.2 s later,
// warm-started from the first plan against cold. The pose search of the fallbacks through a door
// that opens on a wall, and exhausting its expansions where there is no way. The memory of
// obstacles beyond the rolling map: a 30 m map at 0.2 m recorded into it, and the ways round the
// remembered obstacles from a goal over a 60 x 60 m world.
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "common/random.h"
#include "planner/astar.h"
#include "planner/cost_field.h"
#include "planner/cost_map.h"
#include "planner/navigation_planner.h"
#include "planner/obstacle_memory.h"
#include "planner/ompl/ompl_planner.h"
#include "planner/pose_search.h"

namespace {

trav::common::GridLayers CostMap(double resolution_m = 0.1) {
  trav::common::GridLayers map(trav::common::GridGeometry::Centered(
                                   Eigen::Vector2d::Zero(), Eigen::Vector2d(50, 50), resolution_m),
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

// Arguments: resolution [cm], w.
void BM_AStarAcrossTheMap(benchmark::State& state) {
  const trav::common::GridLayers map = CostMap(0.01 * static_cast<double>(state.range(0)));
  trav::planner::AStarConfig config;
  config.cost_weight = static_cast<double>(state.range(1));
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
BENCHMARK(BM_AStarAcrossTheMap)
    ->ArgNames({"cm", "w"})
    ->Args({10, 0})
    ->Args({10, 5})
    ->Args({20, 0})
    ->Args({20, 5})
    ->Unit(benchmark::kMillisecond);

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

// 30 x 30 m at 0.1 m, cost 0.2 with a smooth ridge, and 10 lethal discs of 0.4 to 0.8 m placed
// along the straight 20 m route from (-10, 0) to (10, 0).
trav::common::GridLayers RouteMap() {
  trav::common::GridLayers map(
      trav::common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(30, 30), 0.1),
      {"traversability"});
  trav::common::Random random(5);
  std::vector<std::pair<Eigen::Vector2d, double>> discs;
  for (int k = 0; k < 10; ++k) {
    discs.emplace_back(Eigen::Vector2d(-7.5 + 1.6 * k, random.Uniform(-1.0, 1.0)),
                       random.Uniform(0.4, 0.8));
  }
  const trav::common::GridGeometry& g = map.geometry();
  Eigen::MatrixXf& cost = map.Layer("traversability");
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      cost(ix, iy) = static_cast<float>(0.2 + 0.15 * std::sin(0.5 * p.y()));
      for (const auto& [centre, radius] : discs) {
        if ((p - centre).norm() < radius) cost(ix, iy) = 1.0f;
      }
    }
  }
  return map;
}

trav::common::TrajectoryPoint RouteStart() {
  trav::common::TrajectoryPoint start;
  start.position_W = Eigen::Vector2d(-10, 0);
  return start;
}
const Eigen::Vector2d kRouteGoal(10, 0);

void Report(benchmark::State& state, const trav::planner::NavigationPlan& plan) {
  state.counters["search_ms"] = 1e3 * plan.search_time_s;
  state.counters["optimize_ms"] = 1e3 * plan.optimization_time_s;
  state.counters["iterations"] = plan.optimized.diagnostics.iterations;
  state.counters["pieces"] = plan.optimized.diagnostics.pieces;
  state.counters["planned"] = plan.status == trav::planner::NavigationStatus::kPlanned;
  state.counters["max_violation"] = plan.optimized.diagnostics.max_violation;
  state.counters["rounds"] = plan.optimized.diagnostics.rounds;
  state.counters["terminal_error_m"] = plan.optimized.diagnostics.terminal_error_m;
  state.counters["evaluations"] = plan.optimized.diagnostics.evaluations;
}

void BM_PlanAndOptimize20m(benchmark::State& state) {
  const trav::common::GridLayers map = RouteMap();
  trav::planner::NavigationPlan plan;
  for (auto _ : state) {
    trav::planner::NavigationPlanner planner(trav::planner::NavigationPlannerConfig{});
    plan = planner.Plan(map, RouteStart(), kRouteGoal, {});
    benchmark::DoNotOptimize(plan.optimized.trajectory.points().size());
  }
  Report(state, plan);
}
BENCHMARK(BM_PlanAndOptimize20m)->Unit(benchmark::kMillisecond);

// The first plan is made once; each iteration replans from its state 0.2 s in, on the same map
// toward the same goal, from a copy of the planner that made it (warm) or a reset one (cold).
void BM_Replan20m(benchmark::State& state, bool warm) {
  const trav::common::GridLayers map = RouteMap();
  trav::planner::NavigationPlanner first(trav::planner::NavigationPlannerConfig{});
  const trav::planner::NavigationPlan initial = first.Plan(map, RouteStart(), kRouteGoal, {});
  const trav::common::TrajectoryPoint start = initial.optimized.trajectory.Sample(0.2);
  trav::planner::NavigationPlan plan;
  for (auto _ : state) {
    state.PauseTiming();
    trav::planner::NavigationPlanner planner = first;
    if (!warm) planner.Reset();
    state.ResumeTiming();
    plan = planner.Plan(map, start, kRouteGoal, {});
    benchmark::DoNotOptimize(plan.optimized.trajectory.points().size());
  }
  Report(state, plan);
  state.counters["warm_started"] = plan.optimized.diagnostics.warm_started;
}
BENCHMARK_CAPTURE(BM_Replan20m, warm, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Replan20m, cold, false)->Unit(benchmark::kMillisecond);

// 12 x 12 m at 0.2 m (the mappers' resolution): a wall at x = 0 with a 1.2 m door, a 3 m wall
// across it 1.4 m into the room; closed (no door) when `closed`.
trav::common::GridLayers DoorMap(bool closed) {
  trav::common::GridLayers map(
      trav::common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(12, 12), 0.2),
      {"traversability"});
  const trav::common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d p = g.CellCenter(ix, iy);
      const bool wall = std::abs(p.x()) < 0.15 && (closed || std::abs(p.y()) > 0.6);
      const bool across = std::abs(p.x() - 1.5) < 0.15 && std::abs(p.y()) < 1.5;
      map.Layer("traversability")(ix, iy) = wall || across ? 1.0f : 0.1f;
    }
  }
  return map;
}

// One search from the robot before the door, facing it, to a point round the wall across it.
// Counters: poses of the way (or 0), and whether one was found.
void BM_PoseSearch(benchmark::State& state, bool closed) {
  const trav::common::GridLayers map = DoorMap(closed);
  const trav::planner::NavigationPlannerConfig config;
  const trav::planner::CostField field(map, config.SearchConfig());
  const std::vector<Eigen::Vector2d> body_B = config.footprint.BoundaryPoints_B(0.2);
  trav::common::Pose2 start;
  start.position = Eigen::Vector2d(-1.0, 0.0);
  std::optional<std::vector<trav::common::Pose2>> poses;
  for (auto _ : state) {
    poses = trav::planner::SearchPoses(field, body_B, config.footprint.CircumscribedRadius(),
                                       config.optimizer.clearance_m, start, {2.5, 2.5},
                                       trav::planner::FallbackConfig{});
    benchmark::DoNotOptimize(poses.has_value());
  }
  state.counters["found"] = poses.has_value();
  state.counters["poses"] = poses ? static_cast<double>(poses->size()) : 0.0;
}
BENCHMARK_CAPTURE(BM_PoseSearch, through_a_door, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PoseSearch, no_way, true)->Unit(benchmark::kMillisecond);

// Extents on `g` that put a box of half a 0.2 m cell's side in the middle of every cell.
trav::planner::CellExtents HalfCellBoxes(const trav::common::GridGeometry& g) {
  trav::planner::CellExtents extents;
  extents.x_low = Eigen::MatrixXf::Constant(g.num_x, g.num_y, -0.05f);
  extents.x_high = Eigen::MatrixXf::Constant(g.num_x, g.num_y, 0.05f);
  extents.y_low = extents.x_low;
  extents.y_high = extents.x_high;
  return extents;
}

}  // namespace

// ObstacleDistance on the 50 x 50 m map at the closed loop's 0.2 m (150 lethal discs), every
// lethal cell holding a box of half its side (`with_extents`) or whole: what the boxes add to each
// map update's cost field and search costs.
void BM_ObstacleDistance(benchmark::State& state, bool with_extents) {
  const trav::common::GridLayers map = CostMap(0.2);
  const trav::common::GridGeometry& g = map.geometry();
  const Eigen::MatrixXf& cost = map.Layer("traversability");
  const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> lethal =
      (cost.array() >= 0.8f).matrix();
  const trav::planner::CellExtents extents =
      with_extents ? HalfCellBoxes(g) : trav::planner::CellExtents{};
  for (auto _ : state) {
    benchmark::DoNotOptimize(trav::planner::ObstacleDistance(g, lethal, extents));
  }
}
BENCHMARK_CAPTURE(BM_ObstacleDistance, whole_cells, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ObstacleDistance, boxes, true)->Unit(benchmark::kMillisecond);

// The same map's cost field (`build`: its construction, with the nearest box of every centre
// within CostField::kExactBand_m when the lethal cells hold boxes) or 10,000 of its distance
// queries at points within 0.5 m of the discs' edges (`query`: bilinear only without boxes, the
// Euclidean distance to the nearest box with them).
void BM_CostFieldDistance(benchmark::State& state, bool with_extents, bool query) {
  const trav::common::GridLayers map = CostMap(0.2);
  const trav::common::GridGeometry& g = map.geometry();
  const Eigen::MatrixXf& cost = map.Layer("traversability");
  const trav::planner::CellExtents extents =
      with_extents ? HalfCellBoxes(g) : trav::planner::CellExtents{};
  const trav::planner::CostMapConfig config;
  if (!query) {
    for (auto _ : state) {
      const trav::planner::CostField field(g, cost, config, nullptr, nullptr, extents);
      benchmark::DoNotOptimize(&field);
    }
    return;
  }
  const trav::planner::CostField field(g, cost, config, nullptr, nullptr, extents);
  trav::common::Random random(3);
  std::vector<Eigen::Vector2d> points;
  while (points.size() < 10000) {
    const Eigen::Vector2d p(random.Uniform(-24.0, 24.0), random.Uniform(-24.0, 24.0));
    const double d = field.Distance(p).value;
    if (d > 0.0 && d < 0.5) points.push_back(p);
  }
  for (auto _ : state) {
    double sum = 0.0;
    for (const Eigen::Vector2d& p : points) sum += field.Distance(p).value;
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK_CAPTURE(BM_CostFieldDistance, build_whole_cells, false, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CostFieldDistance, build_boxes, true, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CostFieldDistance, query_whole_cells, false, true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CostFieldDistance, query_boxes, true, true)->Unit(benchmark::kMillisecond);

// A 60 x 60 m world's memory at 0.2 m (301 x 301 cells) holding the obstacles of the 50 m map.
trav::planner::ObstacleMemory WorldMemory() {
  const trav::common::GridLayers map = CostMap(0.2);
  trav::planner::ObstacleMemory memory(
      Eigen::AlignedBox2d(Eigen::Vector2d(-30, -30), Eigen::Vector2d(30, 30)), map.geometry());
  memory.Record(map.geometry(), map.Layer("traversability"), trav::planner::CostMapConfig{});
  return memory;
}

// Recording the default 30 m map (151 x 151 cells) into it: once per map update in the loop.
void BM_ObstacleMemoryRecord(benchmark::State& state) {
  trav::planner::ObstacleMemory memory = WorldMemory();
  const trav::common::GridLayers world = CostMap(0.2);
  trav::common::GridLayers map(
      trav::common::GridGeometry::Centered(Eigen::Vector2d(5, 5), Eigen::Vector2d(30, 30), 0.2),
      {"traversability"});
  const trav::common::GridGeometry& g = map.geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const std::optional<Eigen::Vector2i> cell = world.geometry().CellIndex(g.CellCenter(ix, iy));
      map.Layer("traversability")(ix, iy) = world.Layer("traversability")(cell->x(), cell->y());
    }
  }
  const trav::planner::CostMapConfig config;
  for (auto _ : state) {
    // copied first, as NavigationPlanner::Remember does while a CostMap holds the memory
    trav::planner::ObstacleMemory copy = memory;
    copy.Record(g, map.Layer("traversability"), config);
    benchmark::DoNotOptimize(copy);
  }
}
BENCHMARK(BM_ObstacleMemoryRecord)->Unit(benchmark::kMicrosecond);

// The ways round the remembered obstacles from a goal in a corner: A*'s work where the straight
// line on from the map's edge crosses a remembered obstacle.
void BM_ObstacleMemoryDistances(benchmark::State& state) {
  const trav::planner::ObstacleMemory memory = WorldMemory();
  for (auto _ : state) benchmark::DoNotOptimize(memory.DistancesFrom(kGoal));
}
BENCHMARK(BM_ObstacleMemoryDistances)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
