#include "scenarios/run/plugins.h"

#include <map>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "common/input_error.h"
#include "controller/mpc_tracker.h"
#include "mapping/baselines.h"
#include "mapping/fsgp_bgk_mapper.h"
#include "planner/navigation/navigator.h"
#include "planner/ompl/ompl_planner.h"

namespace trav::scenarios {
namespace {

// A sampling query's wall-time limit [s]: a guard against a query that never ends, far above
// what `planner.sampling_iterations` takes, so that the iteration cap alone ends a query and
// runs repeat whatever the machine's load.
constexpr double kSamplingTimeGuard_s = 60.0;

// Names keyed to factories, built-ins first; guarded, as users register from their own code.
template <typename Factory>
class Registry {
 public:
  explicit Registry(std::map<std::string, Factory> built_in) : factories_(std::move(built_in)) {}

  void Add(const std::string& name, Factory factory) {
    const bool valid =
        !name.empty() &&
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-_") == std::string::npos;
    if (!valid) throw std::invalid_argument("a method name needs [a-z0-9_-]: '" + name + "'");
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!factories_.emplace(name, std::move(factory)).second) {
      throw std::invalid_argument("method '" + name + "' is registered already");
    }
  }

  std::vector<std::string> Names() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> names;
    for (const auto& [name, factory] : factories_) names.push_back(name);
    return names;
  }

  const Factory& Find(const std::string& key, const std::string& name) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto found = factories_.find(name);
    if (found != factories_.end()) return found->second;
    std::string names;
    for (const auto& [known, factory] : factories_) names += (names.empty() ? "" : ", ") + known;
    throw common::InputError("", key,
                             "unknown method " + common::QuotedExcerpt(name) + " (one of " + names +
                                 ", or one a program registered)");
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, Factory> factories_;  // map: entries stay put while others are added
};

Registry<MapperFactory>& Mappers() {
  static Registry<MapperFactory> registry({
      {"fsgp-bgk",
       [](const Scenario& s) { return std::make_unique<mapping::FsgpBgkMapper>(s.mapping); }},
      {"fsgp",
       [](const Scenario& s) {
         mapping::FsgpConfig fsgp = s.mapping;
         fsgp.fuse = false;
         return std::make_unique<mapping::FsgpBgkMapper>(fsgp);
       }},
      {"fsgp-accumulation",
       [](const Scenario& s) {
         mapping::FsgpConfig fsgp = s.mapping;
         fsgp.fuse = false;
         if (fsgp.accumulate_frames == 1) fsgp.accumulate_frames = 5;
         return std::make_unique<mapping::FsgpBgkMapper>(fsgp);
       }},
      {"sgp",
       [](const Scenario& s) {
         mapping::SgpConfig sgp;
         sgp.area = s.mapping.area;
         // M: the inducing points of every GP mapper
         sgp.inducing_points = s.mapping.max_training_points;
         sgp.variance_stride = s.mapping.variance_stride;
         return std::make_unique<mapping::SgpMapper>(sgp);
       }},
      {"em",
       [](const Scenario& s) {
         mapping::ElevationMapConfig em;
         em.area = s.mapping.area;
         return std::make_unique<mapping::ElevationMapper>(em, s.mapping);
       }},
      {"ground-truth",
       [](const Scenario&) { return std::unique_ptr<mapping::TraversabilityMapper>(); }},
  });
  return registry;
}

// An OMPL planner as a path search: seeded alike in every query, ended by its iteration cap. A
// sampling planner needs a goal inside the map and free; toward one beyond what is known (the
// usual case while the robot explores) it aims at the goal A* moves to, the reachable cell
// nearest to it, and reports the move as A* does.
PathSearchFactory Sampling(planner::SamplingAlgorithm algorithm) {
  return [algorithm](const Scenario& scenario) -> planner::PathSearch {
    planner::SamplingPlannerConfig config;
    config.algorithm = algorithm;
    config.time_limit_s = kSamplingTimeGuard_s;
    config.max_iterations = static_cast<std::uint32_t>(scenario.sampling_iterations);
    return [config](const planner::SearchCostMap& costs, const Eigen::Vector2d& start_W,
                    const Eigen::Vector2d& goal_W) {
      const planner::GridPath astar = planner::AStarSearch(costs, start_W, goal_W);
      if (astar.status != planner::PlanStatus::kFound &&
          astar.status != planner::PlanStatus::kGoalMoved) {
        return astar;
      }
      planner::GridPath path = planner::PlanSampling(costs, config, start_W, astar.goal_W).path;
      if (path.status == planner::PlanStatus::kFound) {
        path.status = astar.status;
        path.goal_W = astar.goal_W;
      }
      return path;
    };
  };
}

Registry<PathSearchFactory>& PathSearches() {
  static Registry<PathSearchFactory> registry({
      {"astar", [](const Scenario&) { return planner::PathSearch(planner::AStarSearch); }},
      {"rrt_star", Sampling(planner::SamplingAlgorithm::kRrtStar)},
      {"bit_star", Sampling(planner::SamplingAlgorithm::kBitStar)},
      {"rrt_connect", Sampling(planner::SamplingAlgorithm::kRrtConnect)},
  });
  return registry;
}

Registry<ControllerFactory>& Controllers() {
  static Registry<ControllerFactory> registry({
      {"mpc",
       [](const Scenario& s) -> std::unique_ptr<controller::TrajectoryTracker> {
         // the navigator's plans are tracked within the planner's limits
         return std::make_unique<controller::MpcTracker>(
             s.mode == RunMode::kNavigate ? planner::PlanTrackingConfig(s.mpc, s.planner) : s.mpc);
       }},
  });
  return registry;
}

}  // namespace

void RegisterMapper(const std::string& name, MapperFactory factory) {
  Mappers().Add(name, std::move(factory));
}

void RegisterPathSearch(const std::string& name, PathSearchFactory factory) {
  PathSearches().Add(name, std::move(factory));
}

void RegisterController(const std::string& name, ControllerFactory factory) {
  Controllers().Add(name, std::move(factory));
}

std::vector<std::string> MapperNames() { return Mappers().Names(); }
std::vector<std::string> ControllerNames() { return Controllers().Names(); }
std::vector<std::string> PathSearchNames() { return PathSearches().Names(); }

const MapperFactory& FindMapper(const std::string& name) {
  return Mappers().Find("mapping.method", name);
}

const PathSearchFactory& FindPathSearch(const std::string& name) {
  return PathSearches().Find("planner.method", name);
}

const ControllerFactory& FindController(const std::string& name) {
  return Controllers().Find("controller.method", name);
}

}  // namespace trav::scenarios
