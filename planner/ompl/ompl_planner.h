#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "common/enum_names.h"
#include "planner/astar.h"
#include "planner/cost_map.h"

namespace trav::planner {

/// Sampling-based planners from OMPL (Sucan, Moll, Kavraki, "The Open Motion Planning Library",
/// IEEE RAM 2012), baselines to A* on the same costs.
enum class SamplingAlgorithm {
  /// RRT* (Karaman, Frazzoli, "Sampling-based algorithms for optimal motion planning", IJRR 2011):
  /// anytime, asymptotically optimal.
  kRrtStar,
  /// BIT* (Gammell, Barfoot, Srinivasa, "Batch Informed Trees (BIT*)", IJRR 2020): anytime,
  /// asymptotically optimal, searches batches of samples in order of the cost heuristic.
  kBitStar,
  /// RRT-Connect (Kuffner, LaValle, ICRA 2000): two trees grown towards each other; returns the
  /// first path found and ignores the cost (feasibility only).
  kRrtConnect,
};

/// The names of SamplingAlgorithm's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<SamplingAlgorithm>, 3> kSamplingAlgorithmNames{
    {{SamplingAlgorithm::kRrtStar, "rrt-star"},
     {SamplingAlgorithm::kBitStar, "bit-star"},
     {SamplingAlgorithm::kRrtConnect, "rrt-connect"}}};
constexpr const auto& EnumNames(SamplingAlgorithm) { return kSamplingAlgorithmNames; }

/// The algorithm named "rrt-star", "bit-star" or "rrt-connect".
/// @throws std::invalid_argument naming the value if the name is none of these.
SamplingAlgorithm ParseSamplingAlgorithm(const std::string& name);

/// Settings of one sampling-based query.
struct SamplingPlannerConfig {
  SamplingAlgorithm algorithm{SamplingAlgorithm::kRrtStar};
  /// Wall-time budget of the query, OMPL's setup included [s], > 0. RRT* and BIT* use all of it
  /// (they keep improving their path) unless `max_iterations` ends them first; RRT-Connect stops
  /// at its first path.
  double time_limit_s{0.2};
  /// The planner stops after this many iterations (0: no limit). An iteration is one evaluation of
  /// OMPL's termination condition, which RRT*, RRT-Connect and BIT* evaluate once per iteration of
  /// their main loop (one sample for RRT* and RRT-Connect, one edge or batch for BIT*) and a few
  /// times while taking the start and goal. The only budget that makes anytime planners
  /// repeatable.
  std::uint32_t max_iterations{0};
  /// Longest edge RRT* and RRT-Connect add [m], >= 0; 0 = OMPL's default (a fifth of the map's
  /// diagonal). BIT* ignores it (it connects samples within its own shrinking neighbourhood).
  double range_m{0.0};
  /// Seed of every random draw of the query.
  std::uint32_t seed{1};
};

/// Outcome of a sampling-based query.
struct SamplingResult {
  /// status: kFound, kStartBlocked (start blocked or outside the map) or kNoPath (goal blocked or
  /// outside the map, or no path within the budget; never kGoalMoved). points_W: the planner's
  /// vertices from start_W to goal_W exactly, neither simplified nor interpolated. cost: the sum of
  /// SearchCostMap::SegmentCost over the segments of points_W, the same L (1 + w c) as A*'s cost.
  /// expansions: vertices in the planner's tree (both trees for RRT-Connect; BIT*'s samples not yet
  /// connected are not counted).
  GridPath path;
  double planning_time_s{0.0};  ///< wall time of the query, OMPL's setup included [s]
  std::uint32_t iterations{0};  ///< iterations run (see SamplingPlannerConfig::max_iterations)
};

/// Plans from start_W to goal_W with an OMPL planner on `costs`: states are points of the plane
/// bounded by the grid's cells; a state is valid where SearchCostMap::CostAt is finite and a
/// straight motion is valid exactly where SegmentCost is finite (so every edge of a path has a
/// finite cost); RRT* and BIT* minimise the sum of SegmentCost over the edges, with the admissible
/// heuristic L (1 + w min_cost()) for both the cost of a motion and the cost to go. RRT-Connect
/// ignores the cost; its path's cost is still reported.
///
/// Repeatability: every random draw comes from generators seeded by `config.seed` for this query
/// alone (not from OMPL's process-wide seed), so a query budgeted by `max_iterations` (with a time
/// limit it does not reach) returns the same path bit for bit on every call, in any order, on a
/// given build. A query that ends on `time_limit_s` depends on the machine's speed: RRT* and BIT*
/// then return different paths from run to run; RRT-Connect, which stops at its first path,
/// returns the same path whenever it finds one within the limit.
///
/// No path is a status, never an exception. Silences OMPL's console below warnings (process-wide).
/// @throws std::invalid_argument if config.algorithm is not a SamplingAlgorithm, time_limit_s is
/// not positive and finite, or range_m is negative or not finite.
[[nodiscard]] SamplingResult PlanSampling(const SearchCostMap& costs,
                                          const SamplingPlannerConfig& config,
                                          const Eigen::Vector2d& start_W,
                                          const Eigen::Vector2d& goal_W);

}  // namespace trav::planner
