#include "planner/ompl/ompl_planner.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include <ompl/base/DiscreteMotionValidator.h>
#include <ompl/base/OptimizationObjective.h>
#include <ompl/base/PlannerData.h>
#include <ompl/base/PlannerStatus.h>
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/samplers/InformedStateSampler.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>

#include "common/enum_names.h"
#include "common/random.h"
#include "common/stopwatch.h"

namespace trav::planner {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

// Draws per informed sample for BIT*. OMPL lets its own rejection sampler try 2^32 times, which
// spins once the informed set is (numerically) empty, i.e. when a path meets the heuristic's bound;
// BIT* tolerates failed draws.
constexpr unsigned int kRejectionTries = 1000;

Eigen::Vector2d Point(const ob::State* state) {
  const double* values = state->as<ob::RealVectorStateSpace::StateType>()->values;
  return {values[0], values[1]};
}

// Valid states lie on cells that are not blocked.
class CostMapValidityChecker final : public ob::StateValidityChecker {
 public:
  CostMapValidityChecker(ob::SpaceInformation* si, const SearchCostMap& costs)
      : ob::StateValidityChecker(si), costs_(costs) {}

  bool isValid(const ob::State* state) const override {
    return std::isfinite(costs_.CostAt(Point(state)));
  }

 private:
  const SearchCostMap& costs_;
};

// A motion is valid exactly when its SegmentCost is finite, so every edge of a path has a finite
// cost. OMPL's discrete check (at the space's half-cell resolution) answers only the last-valid-
// state query, which none of the three planners asks.
class SegmentMotionValidator final : public ob::DiscreteMotionValidator {
 public:
  SegmentMotionValidator(ob::SpaceInformation* si, const SearchCostMap& costs)
      : ob::DiscreteMotionValidator(si), costs_(costs) {}

  using ob::DiscreteMotionValidator::checkMotion;
  bool checkMotion(const ob::State* s1, const ob::State* s2) const override {
    const bool valid = std::isfinite(costs_.SegmentCost(Point(s1), Point(s2)));
    ++(valid ? valid_ : invalid_);
    return valid;
  }

 private:
  const SearchCostMap& costs_;
};

// Uniform samples in the bounds from a generator of its own seed.
class SeededSampler final : public ob::RealVectorStateSampler {
 public:
  SeededSampler(const ob::StateSpace* space, std::uint32_t seed)
      : ob::RealVectorStateSampler(space) {
    rng_.setLocalSeed(seed);
  }
};

// Rejection sampling of BIT*'s informed set (states whose heuristic path cost lies in
// [min_cost, max_cost)) from the space's seeded sampler; OMPL's RejectionInfSampler draws from an
// unseeded one.
class SeededRejectionSampler final : public ob::InformedSampler {
 public:
  SeededRejectionSampler(const ob::ProblemDefinitionPtr& problem, unsigned int max_tries)
      : ob::InformedSampler(problem, max_tries), sampler_(space_->allocStateSampler()) {}

  bool sampleUniform(ob::State* state, const ob::Cost& max_cost) override {
    return sampleUniform(state, opt_->identityCost(), max_cost);
  }

  bool sampleUniform(ob::State* state, const ob::Cost& min_cost,
                     const ob::Cost& max_cost) override {
    for (unsigned int i = 0; i < numIters_; ++i) {
      sampler_->sampleUniform(state);
      const ob::Cost cost = heuristicSolnCost(state);
      if (opt_->isCostBetterThan(cost, max_cost) && !opt_->isCostBetterThan(cost, min_cost)) {
        return true;
      }
    }
    return false;
  }

  bool hasInformedMeasure() const override { return false; }
  double getInformedMeasure(const ob::Cost&) const override { return space_->getMeasure(); }
  double getInformedMeasure(const ob::Cost&, const ob::Cost&) const override {
    return space_->getMeasure();
  }

 private:
  ob::StateSamplerPtr sampler_;
};

// The sum of SegmentCost over a path's motions. Every metre costs at least 1 + w min_cost(), so
// the length times that bounds the cost of a motion and the cost to go from below.
class SegmentCostObjective final : public ob::OptimizationObjective {
 public:
  SegmentCostObjective(const ob::SpaceInformationPtr& si, const SearchCostMap& costs,
                       const Eigen::Vector2d& goal_W)
      : ob::OptimizationObjective(si),
        costs_(costs),
        cheapest_per_m_(1.0 + costs.config().cost_weight * costs.min_cost()) {
    description_ = "L (1 + w c) on the search cost map";
    setCostToGoHeuristic([this, goal_W](const ob::State* state, const ob::Goal*) {
      return ob::Cost(cheapest_per_m_ * (goal_W - Point(state)).norm());
    });
  }

  ob::Cost stateCost(const ob::State*) const override { return identityCost(); }

  ob::Cost motionCost(const ob::State* s1, const ob::State* s2) const override {
    return ob::Cost(costs_.SegmentCost(Point(s1), Point(s2)));
  }

  ob::Cost motionCostHeuristic(const ob::State* s1, const ob::State* s2) const override {
    return ob::Cost(cheapest_per_m_ * (Point(s2) - Point(s1)).norm());
  }

  ob::InformedSamplerPtr allocInformedStateSampler(const ob::ProblemDefinitionPtr& problem,
                                                   unsigned int max_tries) const override {
    return std::make_shared<SeededRejectionSampler>(problem, std::min(max_tries, kRejectionTries));
  }

 private:
  const SearchCostMap& costs_;
  double cheapest_per_m_;
};

// An OMPL planner whose own generator is seeded (RRT* draws its goal bias from it).
template <typename Planner>
class Seeded final : public Planner {
 public:
  Seeded(const ob::SpaceInformationPtr& si, std::uint32_t seed) : Planner(si) {
    this->rng_.setLocalSeed(seed);
  }
};

void Validate(const SamplingPlannerConfig& config) {
  auto fail = [](const char* field, double value, const char* requirement) {
    std::ostringstream message;
    message << "SamplingPlannerConfig." << field << " must be " << requirement << ", got " << value;
    throw std::invalid_argument(message.str());
  };
  if (std::string(common::NameOf(config.algorithm)) == "?") {
    fail("algorithm", static_cast<int>(config.algorithm), "a SamplingAlgorithm");
  }
  if (!(config.time_limit_s > 0.0) || !std::isfinite(config.time_limit_s)) {
    fail("time_limit_s", config.time_limit_s, "positive and finite");
  }
  if (!(config.range_m >= 0.0) || !std::isfinite(config.range_m)) {
    fail("range_m", config.range_m, ">= 0 and finite");
  }
}

// The plane bounded by the grid's cells, states valid on free cells, motions checked every half
// cell, sampled from seeds drawn from `seeds`.
ob::SpaceInformationPtr SpaceOf(const SearchCostMap& costs, common::Random* seeds) {
  const common::GridGeometry& g = costs.geometry();
  const Eigen::Vector2d low_W = g.origin_W - Eigen::Vector2d::Constant(0.5 * g.resolution_m);
  const Eigen::Vector2d high_W = low_W + g.resolution_m * Eigen::Vector2d(g.num_x, g.num_y);
  auto space = std::make_shared<ob::RealVectorStateSpace>(2);
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, low_W.x());
  bounds.setLow(1, low_W.y());
  bounds.setHigh(0, high_W.x());
  bounds.setHigh(1, high_W.y());
  space->setBounds(bounds);
  space->setLongestValidSegmentFraction(0.5 * g.resolution_m / space->getMaximumExtent());
  space->setStateSamplerAllocator(
      [sampler_seeds = common::Random(seeds->Next())](const ob::StateSpace* s) mutable {
        return std::make_shared<SeededSampler>(s, static_cast<std::uint32_t>(sampler_seeds.Next()));
      });
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker(std::make_shared<CostMapValidityChecker>(si.get(), costs));
  si->setMotionValidator(std::make_shared<SegmentMotionValidator>(si.get(), costs));
  si->setup();

  return si;
}

// The planner of `algorithm` on `si`, seeded.
ob::PlannerPtr MakePlanner(const SamplingPlannerConfig& config, const ob::SpaceInformationPtr& si,
                           std::uint32_t planner_seed) {
  ob::PlannerPtr planner;
  switch (config.algorithm) {
    case SamplingAlgorithm::kRrtStar: {
      auto rrt_star = std::make_shared<Seeded<og::RRTstar>>(si, planner_seed);
      if (config.range_m > 0.0) rrt_star->setRange(config.range_m);
      planner = rrt_star;
      break;
    }
    case SamplingAlgorithm::kBitStar:
      // BIT* draws only from the informed sampler (its own generator serves just-in-time
      // sampling, which is off); OMPL names its default k-nearest variant "kBITstar"
      planner = std::make_shared<og::BITstar>(si, "kBITstar");
      break;
    case SamplingAlgorithm::kRrtConnect: {
      auto rrt_connect = std::make_shared<Seeded<og::RRTConnect>>(si, planner_seed);
      if (config.range_m > 0.0) rrt_connect->setRange(config.range_m);
      planner = rrt_connect;
      break;
    }
  }
  return planner;
}

}  // namespace

SamplingAlgorithm ParseSamplingAlgorithm(const std::string& name) {
  const std::optional<SamplingAlgorithm> algorithm = common::EnumFromName<SamplingAlgorithm>(name);
  if (!algorithm) {
    throw std::invalid_argument("unknown sampling algorithm '" + name + "' (" +
                                common::EnumNameList<SamplingAlgorithm>() + ")");
  }
  return *algorithm;
}

SamplingResult PlanSampling(const SearchCostMap& costs, const SamplingPlannerConfig& config,
                            const Eigen::Vector2d& start_W, const Eigen::Vector2d& goal_W) {
  Validate(config);
  const common::Stopwatch started;
  auto elapsed_s = [&] { return started.ElapsedSeconds(); };
  SamplingResult result;
  GridPath& path = result.path;
  // the ends first, as A* checks them; a blocked goal is not moved
  if (!std::isfinite(costs.CostAt(start_W)) || !std::isfinite(costs.CostAt(goal_W))) {
    path.status =
        std::isfinite(costs.CostAt(start_W)) ? PlanStatus::kNoPath : PlanStatus::kStartBlocked;
    result.planning_time_s = elapsed_s();
    return result;
  }
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  common::Random seeds(config.seed);

  const ob::SpaceInformationPtr si = SpaceOf(costs, &seeds);
  const auto space = si->getStateSpace();

  // the query and its cost
  ob::ScopedState<ob::RealVectorStateSpace> start(space), goal(space);
  start[0] = start_W.x();
  start[1] = start_W.y();
  goal[0] = goal_W.x();
  goal[1] = goal_W.y();
  auto problem = std::make_shared<ob::ProblemDefinition>(si);
  problem->setStartAndGoalStates(start, goal);
  problem->setOptimizationObjective(std::make_shared<SegmentCostObjective>(si, costs, goal_W));

  const ob::PlannerPtr planner = MakePlanner(config, si, static_cast<std::uint32_t>(seeds.Next()));
  planner->setProblemDefinition(problem);
  planner->setup();

  // until the iteration budget or the time limit, whichever comes first
  const ob::PlannerTerminationCondition termination([&] {
    if (config.max_iterations > 0 && result.iterations >= config.max_iterations) return true;
    if (elapsed_s() >= config.time_limit_s) return true;
    ++result.iterations;
    return false;
  });
  const ob::PlannerStatus status = planner->solve(termination);

  // vertices of the tree(s); BIT*'s getPlannerData would keep every sample alive in a static set
  // for the rest of the process, so its progress property is read instead
  if (config.algorithm == SamplingAlgorithm::kBitStar) {
    path.expansions =
        std::stoi(planner->getPlannerProgressProperties().at("current graph vertices INTEGER")());
  } else {
    ob::PlannerData graph(si);
    planner->getPlannerData(graph);
    path.expansions = static_cast<int>(graph.numVertices());
  }
  if (status == ob::PlannerStatus::EXACT_SOLUTION) {
    path.status = PlanStatus::kFound;
    for (const ob::State* state :
         problem->getSolutionPath()->as<og::PathGeometric>()->getStates()) {
      path.points_W.push_back(Point(state));
    }
    path.goal_W = path.points_W.back();
    for (std::size_t i = 1; i < path.points_W.size(); ++i) {
      path.cost += costs.SegmentCost(path.points_W[i - 1], path.points_W[i]);
    }
  } else {
    path.status = PlanStatus::kNoPath;
  }
  result.planning_time_s = elapsed_s();
  return result;
}

}  // namespace trav::planner
