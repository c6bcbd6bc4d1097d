// Mappers and path searches by name (scenarios/run/plugins.h): the built-ins, a registered one run
// in the closed loop, OMPL's planners under `planner.method`, and the errors.
#include "scenarios/run/plugins.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"
#include "common/pose.h"
#include "common/yaml_reader.h"
#include "controller/trajectory_tracker.h"
#include "mapping/baselines.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using testing::HasSubstr;

// Flat ground with a wall across the way between start and goal.
constexpr char kWallWorld[] = R"(
schema_version: 1
mode: navigate
terrain:
  type: flat
  size: [24, 16]
  boxes: [{name: wall, centre: [0, 0], half_extents: [0.2, 3], height: 1.0}]
robot: {start: [-6, 0, 0]}
goal: [6, 0]
duration: 40
video: {enabled: false}
)";

Scenario Load(const std::string& extra) {
  return LoadScenario(common::YamlDocument::Parse(std::string(kWallWorld) + extra, "plugins.yaml"));
}

// Runs a scenario into a fresh folder; returns its summary and trajectory.csv.
RunSummary RunInTemporaryFolder(const Scenario& scenario, const std::string& tag,
                                std::string* trajectory) {
  const fs::path out =
      fs::temp_directory_path() / ("trav_plugins_" + std::to_string(getpid()) + "_" + tag);
  fs::remove_all(out);
  fs::create_directories(out);
  const RunSummary summary =
      RunScenario(scenario, RobotModelPath(scenario, TRAV_MODELS_DIR), out.string());
  std::ifstream file(out / "trajectory.csv");
  std::stringstream text;
  text << file.rdbuf();
  *trajectory = text.str();
  fs::remove_all(out);
  return summary;
}

// Kanayama's tracking law (Kanayama et al., "A stable tracking control method for an autonomous
// mobile robot", ICRA 1990) at 20 Hz: a controller that is not trav's.
class KanayamaTracker : public controller::TrajectoryTracker {
 public:
  void SetReference(common::Trajectory reference) override { reference_ = std::move(reference); }
  bool SolveDue(double t_s) const override { return t_s + 1e-9 >= next_s_; }
  common::Twist2 Command(const common::RobotState& state) override {
    if (!SolveDue(state.time_s)) return command_;
    next_s_ = state.time_s + 0.05;
    const common::TrajectoryPoint r = reference_.Sample(state.time_s);
    const double yaw = common::ToRollPitchYaw(state.X_WB.linear()).yaw;
    // the reference's pose in the robot's frame
    const Eigen::Vector2d d = r.position_W - state.X_WB.translation().head<2>();
    const double e_x = std::cos(yaw) * d.x() + std::sin(yaw) * d.y();
    const double e_y = -std::sin(yaw) * d.x() + std::cos(yaw) * d.y();
    const double e_yaw = std::remainder(r.yaw - yaw, 2.0 * M_PI);
    command_.v = std::clamp(r.v * std::cos(e_yaw) + 1.0 * e_x, -1.0, 1.5);
    command_.omega = std::clamp(r.omega + r.v * (10.0 * e_y + 3.0 * std::sin(e_yaw)), -2.0, 2.0);
    ++solves_;
    return command_;
  }
  controller::TrackingMetrics Metrics() const override {
    controller::TrackingMetrics metrics;
    metrics.solves = solves_;
    return metrics;
  }
  const common::Trajectory& reference() const override { return reference_; }
  int solves() const override { return solves_; }
  const Eigen::Matrix3Xd& predicted_states_W() const override { return none_; }

 private:
  common::Trajectory reference_;
  common::Twist2 command_{};
  double next_s_{0.0};
  int solves_{0};
  Eigen::Matrix3Xd none_;
};

TEST(PluginsTest, TheBuiltInMethodsAreRegisteredByTheirScenarioNames) {
  EXPECT_EQ(MapperNames(), (std::vector<std::string>{"em", "fsgp", "fsgp-accumulation", "fsgp-bgk",
                                                     "ground-truth", "sgp"}));
  EXPECT_EQ(PathSearchNames(),
            (std::vector<std::string>{"astar", "bit_star", "rrt_connect", "rrt_star"}));
  EXPECT_EQ(ControllerNames(), (std::vector<std::string>{"mpc"}));
  const Scenario defaults;
  EXPECT_EQ(FindMapper("ground-truth")(defaults), nullptr);
}

TEST(PluginsTest, UnknownNamesAreBadInputListingTheNames) {
  try {
    Load("mapping: {method: octomap}\n");
    FAIL() << "loaded an unknown mapper";
  } catch (const common::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("plugins.yaml: mapping.method: unknown method 'octomap'"));
    EXPECT_THAT(e.what(), HasSubstr("em, fsgp, fsgp-accumulation, fsgp-bgk, ground-truth, sgp"));
  }
  EXPECT_THROW(Load("planner: {method: prm}\n"), common::InputError);
}

TEST(PluginsTest, NamesAreUniqueAndPlain) {
  const MapperFactory none = [](const Scenario&) { return nullptr; };
  EXPECT_THROW(RegisterMapper("fsgp-bgk", none), std::invalid_argument);
  EXPECT_THROW(RegisterMapper("", none), std::invalid_argument);
  EXPECT_THROW(RegisterMapper("My Mapper", none), std::invalid_argument);
  EXPECT_THROW(RegisterPathSearch("astar", [](const Scenario&) { return planner::PathSearch(); }),
               std::invalid_argument);
}

TEST(PluginsTest, ARegisteredMapperRunsInTheClosedLoopByItsName) {
  // the elevation-map baseline under a name of its own, counting the mappers it makes
  int made = 0;
  RegisterMapper("coarse-em", [&made](const Scenario& s) {
    ++made;
    mapping::ElevationMapConfig em;
    em.area = s.mapping.area;
    return std::make_unique<mapping::ElevationMapper>(em, s.mapping);
  });
  const Scenario scenario = Load("mapping: {method: coarse-em}\n");
  EXPECT_EQ(scenario.mapper, "coarse-em");
  EXPECT_THAT(ResolvedScenarioYaml(scenario), HasSubstr("method: coarse-em"));
  std::string trajectory;
  const RunSummary summary = RunInTemporaryFolder(scenario, "mapper", &trajectory);
  EXPECT_EQ(made, 1);
  EXPECT_EQ(summary.outcome, Outcome::kSuccess);
  ASSERT_TRUE(summary.mapping.has_value());
  EXPECT_EQ(summary.mapping->method, "coarse-em");
  EXPECT_GT(summary.mapping->updates, 50);
}

TEST(PluginsTest, ARegisteredControllerTracksThePlansByItsName) {
  RegisterController("kanayama",
                     [](const Scenario&) { return std::make_unique<KanayamaTracker>(); });
  const Scenario scenario = Load("controller: {method: kanayama}\n");
  std::string trajectory;
  const RunSummary summary = RunInTemporaryFolder(scenario, "controller", &trajectory);
  EXPECT_EQ(summary.outcome, Outcome::kSuccess);
  ASSERT_TRUE(summary.tracking.has_value());
  // at most 20 Hz over the run (the MPC would have solved at its own 50 Hz while driving)
  EXPECT_GT(summary.tracking->solves, 100);
  EXPECT_LE(summary.tracking->solves, 20.0 * summary.sim_time_s + 1.0);
  EXPECT_GT(summary.distance_m, 12.5);
}

TEST(PluginsTest, OmplsPlannersDriveTheClosedLoopRepeatably) {
  // BIT* round the wall: the path search under the trajectory, twice alike, and not A*'s drive
  const Scenario scenario = Load("planner: {method: bit_star, sampling_iterations: 500}\n");
  std::string first, second, astar;
  const RunSummary summary = RunInTemporaryFolder(scenario, "bit_star_1", &first);
  RunInTemporaryFolder(scenario, "bit_star_2", &second);
  RunInTemporaryFolder(Load(""), "astar", &astar);
  EXPECT_NE(first, astar);
  EXPECT_EQ(summary.outcome, Outcome::kSuccess);
  ASSERT_TRUE(summary.navigation.has_value());
  EXPECT_EQ(summary.navigation->failed_plans, 0);
  // round the 6 m wall: longer than the 12 m straight line
  EXPECT_GT(summary.distance_m, 12.5);
  EXPECT_EQ(first, second);
}

}  // namespace
}  // namespace trav::scenarios
