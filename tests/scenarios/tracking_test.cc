// Tracking scenarios end to end: the MPC drives the Scout Mini in MuJoCo along the shipped
// references (scenarios/track/).

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"
#include "scenarios/run/track_reference.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

RunSummary RunTrackingScenario(const std::string& name, const std::string& overrides = "") {
  common::YamlDocument document = common::YamlDocument::Load(std::string(TRAV_SOURCE_DIR) +
                                                             "/scenarios/track/" + name + ".yaml");
  if (!overrides.empty()) document.Set("track.file", overrides);
  const Scenario scenario = LoadScenario(document);
  const fs::path out =
      fs::temp_directory_path() / ("trav_tracking_" + std::to_string(getpid()) + "_" + name);
  fs::create_directories(out);
  const RunSummary summary =
      RunScenario(scenario, std::string(TRAV_MODELS_DIR) + "/scout_mini.xml", out.string());
  fs::remove_all(out);
  return summary;
}

TEST(TrackingScenarioTest, FigureEightAtOneMetrePerSecondOnFlatGround) {
  const RunSummary summary = RunTrackingScenario("figure_eight");
  ASSERT_EQ(summary.outcome, Outcome::kCompleted);
  ASSERT_TRUE(summary.tracking.has_value());
  EXPECT_LE(summary.tracking->rms_lateral_error_m, 0.05);
  EXPECT_LE(summary.tracking->max_lateral_error_m, 0.15);
  EXPECT_EQ(summary.tracking->failures, 0);
  EXPECT_EQ(summary.tracking->solves, 1200);  // 24 s at 50 Hz
}

TEST(TrackingScenarioTest, FigureEightOnHillyTerrain) {
  const RunSummary summary = RunTrackingScenario("figure_eight_hilly");
  ASSERT_EQ(summary.outcome, Outcome::kCompleted);
  EXPECT_LE(summary.tracking->rms_lateral_error_m, 0.10);
  EXPECT_EQ(summary.tracking->failures, 0);
}

TEST(TrackingScenarioTest, SlalomAndCircle) {
  for (const char* name : {"slalom", "circle"}) {
    const RunSummary summary = RunTrackingScenario(name);
    EXPECT_EQ(summary.outcome, Outcome::kCompleted) << name;  // on its terrain to the end
    EXPECT_LE(summary.tracking->rms_lateral_error_m, 0.05) << name;
    EXPECT_LE(summary.tracking->max_lateral_error_m, 0.15) << name;
  }
}

TEST(BuildReferenceTest, ShapesStartAtTheStartPose) {
  TrackSettings settings;
  common::Pose2 start;
  start.position = Eigen::Vector2d(2.0, -1.0);
  start.yaw = M_PI / 2;
  for (ReferenceShape shape : {ReferenceShape::kLine, ReferenceShape::kCircle,
                               ReferenceShape::kFigureEight, ReferenceShape::kSlalom}) {
    settings.reference = shape;
    const common::Trajectory reference = BuildReference(settings, start);
    const common::TrajectoryPoint first = reference.Sample(0.0);
    EXPECT_NEAR((first.position_W - start.position).norm(), 0.0, 1e-9);
    EXPECT_NEAR(std::remainder(first.yaw - start.yaw, 2 * M_PI), 0.0, 0.05);
    EXPECT_EQ(first.v, 0.0);
  }
}

TEST(BuildReferenceTest, ReadsAReferenceFileAndRejectsBadOnes) {
  const fs::path path =
      fs::temp_directory_path() / ("trav_reference_" + std::to_string(getpid()) + ".csv");
  std::ofstream(path) << "t,x,y,yaw,v,omega\n0,1,2,0,0,0\n1,1.5,2,0,1,0\n2,2.5,2,0,1,0\n";
  TrackSettings settings;
  settings.reference = ReferenceShape::kFile;
  settings.file = path.string();
  const common::Trajectory reference = BuildReference(settings, common::Pose2{});
  EXPECT_EQ(reference.points().size(), 3u);
  EXPECT_DOUBLE_EQ(reference.Sample(1.5).position_W.x(), 2.0);
  std::ofstream(path) << "t,x,y,yaw,v,omega\n0,1,2,0,0,0\n0,1.5,2,0,1,0\n";
  EXPECT_THAT([&] { BuildReference(settings, common::Pose2{}); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("line 3: expected 6 finite numbers with increasing t")));
  fs::remove(path);
  EXPECT_THAT([&] { BuildReference(settings, common::Pose2{}); },
              ThrowsMessage<common::InputError>(HasSubstr("cannot open reference trajectory")));
}

TEST(TrackingConfigTest, BadControllerSettingsNameTheKey) {
  auto load = [](const std::string& text) {
    return LoadScenario(common::YamlDocument::Parse(text, "t.yaml"));
  };
  EXPECT_THAT([&] { load("controller: {mpc: {horizon: -5}}"); },
              ThrowsMessage<common::InputError>(HasSubstr(
                  "t.yaml: controller.mpc.horizon: value '-5' is outside its bounds [1, 200]")));
  EXPECT_THAT([&] { load("controller: {mpc: {state_weights: [1, 2]}}"); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("controller.mpc.state_weights: expected a sequence of 3 numbers")));
  EXPECT_THAT([&] { load("controller: {mpc: {rate_weights: [1, -2]}}"); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("controller.mpc.rate_weights: value [1, -2] is outside its bounds")));
  EXPECT_THAT([&] { load("controller: {rate: 0}"); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("controller.rate: value '0' is outside its bounds [5, 1000]")));
  EXPECT_THAT(
      [&] { load("mode: track\ntrack: {reference: file}"); },
      ThrowsMessage<common::InputError>(HasSubstr("track.file: required for reference 'file'")));
}

}  // namespace
}  // namespace trav::scenarios
