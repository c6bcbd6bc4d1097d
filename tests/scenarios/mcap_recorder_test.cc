// run.mcap read back with the MCAP library: its channels, schemas, message counts and timestamps
// against the run's own CSV files and summary.
#include "scenarios/run/mcap_recorder.h"

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <mcap/reader.hpp>
#include <nlohmann/json.hpp>

#include "common/yaml_reader.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

// Column `column` of every row of a CSV file with a header line (0: the time).
std::vector<double> Column(const fs::path& path, int column = 0) {
  std::ifstream file(path);
  std::string line;
  std::getline(file, line);
  std::vector<double> values;
  while (std::getline(file, line)) {
    std::stringstream fields(line);
    std::string field;
    for (int c = 0; c <= column; ++c) std::getline(fields, field, ',');
    values.push_back(std::stod(field));
  }
  return values;
}

struct Topic {
  std::string schema;
  std::string schema_encoding;
  std::string message_encoding;
  std::vector<std::uint64_t> log_times_ns;
  std::vector<nlohmann::json> messages;
};

// Every message of the file by topic, parsed.
std::map<std::string, Topic> ReadMcap(const fs::path& path) {
  mcap::McapReader reader;
  const mcap::Status opened = reader.open(path.string());
  EXPECT_TRUE(opened.ok()) << opened.message;
  std::map<std::string, Topic> topics;
  const auto on_problem = [](const mcap::Status& problem) { ADD_FAILURE() << problem.message; };
  for (const mcap::MessageView& view : reader.readMessages(on_problem)) {
    Topic& topic = topics[view.channel->topic];
    topic.schema = view.schema->name;
    topic.schema_encoding = view.schema->encoding;
    topic.message_encoding = view.channel->messageEncoding;
    topic.log_times_ns.push_back(view.message.logTime);
    const auto* text = reinterpret_cast<const char*>(view.message.data);
    topic.messages.push_back(nlohmann::json::parse(text, text + view.message.dataSize));
  }
  reader.close();
  return topics;
}

// Decodes RFC 4648 base64 (the test's own decoder, independent of the writer's encoder).
std::vector<std::uint8_t> DecodeBase64(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<std::uint8_t> bytes;
  std::uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<std::uint32_t>(alphabet.find(c));
    count += 6;
    if (count >= 8) {
      count -= 8;
      bytes.push_back(static_cast<std::uint8_t>((bits >> count) & 0xff));
    }
  }
  return bytes;
}

// Field `offset` (float32) of element `i` of packed data with `stride` bytes per element.
float FloatAt(const std::vector<std::uint8_t>& data, std::size_t i, int stride, int offset) {
  float value;
  std::memcpy(&value, &data.at(i * stride + offset), sizeof(value));
  return value;
}

double Seconds(const nlohmann::json& time) {
  return time.at("sec").get<double>() + 1e-9 * time.at("nsec").get<double>();
}

class McapRecorderTest : public testing::Test {
 protected:
  // A pedestrian crosses the robot's way on flat ground; the robot perceives it from the scans.
  static void SetUpTestSuite() {
    const Scenario scenario = LoadScenario(common::YamlDocument::Parse(R"(
schema_version: 1
mode: navigate
terrain: {type: flat, size: [20, 12], resolution: 0.1}
robot: {start: [-6, 0, 0]}
goal: [6, 0]
duration: 25
navigation: {movers_from_ground_truth: false}
moving_obstacles:
  - {name: pedestrian, shape: capsule, radius: 0.25, half_height: 0.85, motion: constant_velocity,
     start: [0, -5], velocity: [0, 1.0]}
video: {enabled: false}
output: {mcap: true, mcap_map_period: 0}
)",
                                                                       "mcap_run.yaml"));
    folder_ = new fs::path(fs::temp_directory_path() / ("trav_mcap_" + std::to_string(getpid())));
    fs::remove_all(*folder_);
    fs::create_directories(*folder_);
    summary_ = new RunSummary(
        RunScenario(scenario, RobotModelPath(scenario, TRAV_MODELS_DIR), folder_->string()));
    topics_ = new std::map<std::string, Topic>(ReadMcap(*folder_ / kMcapFileName));
  }
  static void TearDownTestSuite() {
    fs::remove_all(*folder_);
    delete folder_;
    delete summary_;
    delete topics_;
  }

  static const Topic& Get(const std::string& topic) { return topics_->at(topic); }

  static fs::path* folder_;
  static RunSummary* summary_;
  static std::map<std::string, Topic>* topics_;
};

fs::path* McapRecorderTest::folder_ = nullptr;
RunSummary* McapRecorderTest::summary_ = nullptr;
std::map<std::string, Topic>* McapRecorderTest::topics_ = nullptr;

TEST_F(McapRecorderTest, HoldsEveryChannelWithItsFoxgloveSchema) {
  ASSERT_EQ(summary_->outcome, Outcome::kSuccess);
  EXPECT_TRUE(summary_->mcap);
  const std::map<std::string, std::string> expected = {
      {"/tf", "foxglove.FrameTransforms"},
      {"/lidar/points", "foxglove.PointCloud"},
      {"/map", "foxglove.Grid"},
      {"/planner/path", "foxglove.SceneUpdate"},
      {"/planner/trajectory", "foxglove.SceneUpdate"},
      {"/controller/horizon", "foxglove.SceneUpdate"},
      {"/movers/true", "foxglove.SceneUpdate"},
      {"/movers/perceived", "foxglove.SceneUpdate"},
      {"/goal", "foxglove.SceneUpdate"},
      {"/status", "foxglove.Log"},
      {"/timings", "trav.ModuleTimes"}};
  std::map<std::string, std::string> found;
  for (const auto& [name, topic] : *topics_) {
    found[name] = topic.schema;
    EXPECT_EQ(topic.schema_encoding, "jsonschema") << name;
    EXPECT_EQ(topic.message_encoding, "json") << name;
  }
  EXPECT_EQ(found, expected);
}

TEST_F(McapRecorderTest, TransformsAreTheTrajectoryRowsAndTheirTimes) {
  const std::vector<double> rows = Column(*folder_ / "trajectory.csv");
  const Topic& tf = Get("/tf");
  ASSERT_EQ(tf.messages.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    // trajectory.csv prints the time in ms
    ASSERT_NEAR(1e-9 * static_cast<double>(tf.log_times_ns[i]), rows[i], 5e-4) << i;
    const nlohmann::json& transforms = tf.messages[i].at("transforms");
    ASSERT_EQ(transforms.size(), 3u);
    EXPECT_EQ(transforms[0].at("parent_frame_id"), "world");
    EXPECT_EQ(transforms[0].at("child_frame_id"), "base_link");
    EXPECT_EQ(transforms[1].at("child_frame_id"), "odom");
    EXPECT_EQ(transforms[2].at("parent_frame_id"), "base_link");
    EXPECT_EQ(transforms[2].at("child_frame_id"), "lidar");
    EXPECT_NEAR(Seconds(transforms[0].at("timestamp")), rows[i], 5e-4);
  }
  // true poses: the odometry frame is the world
  EXPECT_NEAR(tf.messages.back()["transforms"][1]["translation"]["x"].get<double>(), 0.0, 1e-12);
  // the base's position is trajectory.csv's (printed to 0.01 mm)
  const std::vector<double> x = Column(*folder_ / "trajectory.csv", 1);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_NEAR(tf.messages[i]["transforms"][0]["translation"]["x"].get<double>(), x[i], 1e-5);
  }
}

TEST_F(McapRecorderTest, EveryFrameMapUpdatePlanAndSolveIsOneMessage) {
  EXPECT_EQ(Get("/lidar/points").messages.size(), static_cast<std::size_t>(summary_->lidar_frames));
  ASSERT_TRUE(summary_->mapping.has_value());
  EXPECT_EQ(Get("/map").messages.size(), static_cast<std::size_t>(summary_->mapping->updates));
  ASSERT_TRUE(summary_->navigation.has_value());
  EXPECT_EQ(Get("/planner/path").messages.size(),
            static_cast<std::size_t>(summary_->navigation->plans));
  EXPECT_EQ(Get("/planner/trajectory").messages.size(),
            static_cast<std::size_t>(summary_->navigation->plans));
  EXPECT_EQ(Get("/controller/horizon").messages.size(),
            static_cast<std::size_t>(summary_->tracking->solves));
  // the time series' rows, at their times
  const std::vector<double> rows = Column(*folder_ / "timeseries.csv");
  for (const char* topic : {"/timings", "/movers/true", "/movers/perceived"}) {
    ASSERT_EQ(Get(topic).messages.size(), rows.size()) << topic;
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_NEAR(Get("/timings").messages[i].at("t").get<double>(), rows[i], 5e-4);
  }
  // the pedestrian is drawn while it is in the world
  EXPECT_EQ(Get("/movers/true").messages[0]["entities"][0]["cylinders"].size(), 1u);
  // the run starts and ends with a status line
  EXPECT_EQ(Get("/status").messages.front().at("message").get<std::string>().rfind("start", 0), 0u);
  EXPECT_EQ(Get("/status").messages.back().at("message"), "outcome: success");
}

TEST_F(McapRecorderTest, PointCloudsAndGridsCarryTheirData) {
  const nlohmann::json& cloud = Get("/lidar/points").messages.at(5);
  EXPECT_EQ(cloud.at("frame_id"), "world");
  EXPECT_EQ(cloud.at("point_stride"), 20);
  std::vector<std::string> fields;
  for (const nlohmann::json& field : cloud.at("fields")) fields.push_back(field.at("name"));
  EXPECT_EQ(fields, (std::vector<std::string>{"x", "y", "z", "intensity", "time"}));
  // whole 20-byte points on the flat 20 x 12 m world (ground at z = 0) or the pedestrian, each
  // with its reflectivity and its time in the 0.1 s frame
  const std::vector<std::uint8_t> points = DecodeBase64(cloud.at("data"));
  ASSERT_GT(points.size(), 0u);
  ASSERT_EQ(points.size() % 20, 0u);
  for (std::size_t i = 0; i < points.size() / 20; ++i) {
    ASSERT_LE(std::abs(FloatAt(points, i, 20, 0)), 10.1f) << i;
    ASSERT_LE(std::abs(FloatAt(points, i, 20, 4)), 6.1f) << i;
    ASSERT_GE(FloatAt(points, i, 20, 8), -0.1f) << i;
    ASSERT_LE(FloatAt(points, i, 20, 8), 1.8f) << i;
    ASSERT_GE(FloatAt(points, i, 20, 12), 0.0f) << i;
    ASSERT_LE(FloatAt(points, i, 20, 12), 255.0f) << i;
    ASSERT_GE(FloatAt(points, i, 20, 16), 0.0f) << i;
    ASSERT_LT(FloatAt(points, i, 20, 16), 0.1f) << i;
  }

  const nlohmann::json& grid = Get("/map").messages.back();
  EXPECT_EQ(grid.at("frame_id"), "odom");
  const int columns = grid.at("column_count");
  const int cell_stride = grid.at("cell_stride");
  EXPECT_EQ(cell_stride, 4 * static_cast<int>(grid.at("fields").size()));
  EXPECT_EQ(grid.at("row_stride").get<int>(), columns * cell_stride);
  std::map<std::string, int> offsets;
  for (const nlohmann::json& field : grid.at("fields"))
    offsets[field.at("name")] = field.at("offset");
  ASSERT_EQ(offsets.count("traversability"), 1u);
  ASSERT_EQ(offsets.count("elevation"), 1u);
  // a square map of rows * row_stride bytes; on flat ground every known cell is traversable and
  // at the ground's height
  const std::vector<std::uint8_t> cells = DecodeBase64(grid.at("data"));
  ASSERT_EQ(cells.size(), static_cast<std::size_t>(columns) * columns * cell_stride);
  int known = 0;
  for (std::size_t i = 0; i < cells.size() / cell_stride; ++i) {
    const float cost = FloatAt(cells, i, cell_stride, offsets["traversability"]);
    if (std::isnan(cost)) continue;
    ++known;
    EXPECT_GE(cost, 0.0f);
    EXPECT_LE(cost, 1.0f);
    EXPECT_NEAR(FloatAt(cells, i, cell_stride, offsets["elevation"]), 0.0f, 0.05f);
  }
  EXPECT_GT(known, 1000);
}

TEST_F(McapRecorderTest, TheShippedFoxgloveLayoutShowsTopicsAndFieldsTheFileHas) {
  std::ifstream file(std::string(TRAV_SOURCE_DIR) + "/docs/foxglove-layout.json");
  const nlohmann::json layout = nlohmann::json::parse(file);
  const nlohmann::json& panels = layout.at("configById");
  int topics = 0;
  for (const auto& [topic, settings] : panels.at("3D!trav").at("topics").items()) {
    EXPECT_EQ(topics_->count(topic), 1u) << topic;
    ++topics;
  }
  EXPECT_EQ(topics, 8);
  const nlohmann::json& timings = Get("/timings").messages.front();
  for (const nlohmann::json& path : panels.at("Plot!timings").at("paths")) {
    const std::string value = path.at("value");
    ASSERT_EQ(value.rfind("/timings.", 0), 0u) << value;
    EXPECT_TRUE(timings.contains(value.substr(std::string("/timings.").size()))) << value;
  }
}

TEST_F(McapRecorderTest, TimesNeverGoBackOnAnyChannel) {
  for (const auto& [name, topic] : *topics_) {
    for (std::size_t i = 1; i < topic.log_times_ns.size(); ++i) {
      ASSERT_LE(topic.log_times_ns[i - 1], topic.log_times_ns[i]) << name << " " << i;
    }
  }
}

}  // namespace
}  // namespace trav::scenarios
