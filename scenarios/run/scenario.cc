#include "scenarios/run/scenario.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <sstream>
#include <type_traits>
#include <utility>
#include <variant>

#include <yaml-cpp/yaml.h>

#include "common/archive.h"
#include "common/enum_names.h"
#include "common/input_error.h"
#include "scenarios/run/plugins.h"
#include "scenarios/run/terrain_files.h"

namespace trav::scenarios {
namespace {

using common::Bounds;

// Fields that need no bounds: flags, text, and 64-bit seeds (every value is a valid seed).
template <typename T>
constexpr bool kUnbounded =
    std::is_same_v<T, bool> || std::is_same_v<T, std::string> || std::is_same_v<T, std::uint64_t>;

// The smallest and largest component of a numeric value.
std::pair<double, double> Extremes(double v) { return {v, v}; }
std::pair<double, double> Extremes(int v) { return {v, v}; }
template <int N>
std::pair<double, double> Extremes(const Eigen::Matrix<double, N, 1>& v) {
  return {v.minCoeff(), v.maxCoeff()};
}
std::pair<double, double> Extremes(const std::array<double, 2>& v) {
  return {std::min(v[0], v[1]), std::max(v[0], v[1])};
}
std::pair<double, double> Extremes(const common::Pose2& pose) {
  return {std::min({pose.position.x(), pose.position.y(), pose.yaw}),
          std::max({pose.position.x(), pose.position.y(), pose.yaw})};
}
std::pair<double, double> Extremes(const std::optional<Eigen::Matrix<double, 6, 1>>& value) {
  return value ? Extremes(*value) : std::make_pair(0.0, 0.0);
}
std::pair<double, double> Extremes(const std::vector<Eigen::Vector2d>& points) {
  std::pair<double, double> extremes{0.0, 0.0};
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [low, high] = Extremes(points[i]);
    extremes = i == 0
                   ? std::make_pair(low, high)
                   : std::make_pair(std::min(extremes.first, low), std::max(extremes.second, high));
  }
  return extremes;
}

std::string BoundsText(const Bounds& bounds) {
  std::ostringstream text;
  text << "[" << bounds.min << ", " << bounds.max << "]";
  return text.str();
}

// Items that together reach every key of a sequence's items: T::KeyExamples() where T has it.
template <typename T, typename = void>
struct HasKeyExamples : std::false_type {};
template <typename T>
struct HasKeyExamples<T, std::void_t<decltype(T::KeyExamples())>> : std::true_type {};
template <typename T>
std::vector<T> KeyExamples() {
  if constexpr (HasKeyExamples<T>::value) {
    return T::KeyExamples();
  } else {
    return {T{}};
  }
}

// Reads a scenario file strictly (common/archive.h): every key is checked against its type and
// bounds, and a map with a key nobody visited is an error.
class ReadArchive {
 public:
  explicit ReadArchive(common::YamlReader reader) : reader_(std::move(reader)) {}

  template <typename T>
  void Field(const std::string& key, T* value) {
    static_assert(kUnbounded<T>, "a numeric scenario key needs its Bounds");
    reader_.Read(key, value);
  }
  template <typename T>
  void Field(const std::string& key, T* value, const Bounds& bounds) {
    Read(key, value);
    if (!reader_.Has(key)) return;
    const auto [low, high] = Extremes(*value);
    reader_.Check(key, low >= bounds.min && high <= bounds.max,
                  "is outside its bounds " + BoundsText(bounds));
  }
  template <typename E>
  void Enum(const std::string& key, E* value) {
    reader_.ReadEnum(key, value);
  }
  void Map(const std::string& key, const std::function<void(ReadArchive&)>& visit) {
    if (!reader_.Has(key)) return;
    ReadArchive child(reader_.Map(key));
    visit(child);
    child.reader_.Finish();
  }
  template <typename T>
  void Map(const std::string& key, T* value) {
    Map(key, [value](ReadArchive& child) { value->Serialize(&child); });
  }
  template <typename T>
  void Sequence(const std::string& key, std::vector<T>* items, std::size_t max_items) {
    if (!reader_.Has(key)) return;
    items->clear();
    std::vector<common::YamlReader> readers = reader_.MapSequence(key);
    reader_.Check(key, readers.size() <= max_items,
                  "has " + std::to_string(readers.size()) + " items, more than the " +
                      std::to_string(max_items) + " allowed");
    for (common::YamlReader& item_reader : readers) {
      ReadArchive item(item_reader);
      items->emplace_back();
      items->back().Serialize(&item);
      item.reader_.Finish();
    }
  }
  void Finish() const { reader_.Finish(); }

 private:
  template <typename T>
  void Read(const std::string& key, T* value) {
    reader_.Read(key, value);
  }
  void Read(const std::string& key, std::array<double, 2>* range) {
    Eigen::Vector2d value(range->at(0), range->at(1));
    reader_.Read(key, &value);
    reader_.Check(key, value[0] <= value[1], "must be a range [min, max] with min <= max");
    *range = {value[0], value[1]};
  }
  void Read(const std::string& key, common::Pose2* pose) {
    Eigen::Vector3d value(pose->position.x(), pose->position.y(), pose->yaw);
    reader_.Read(key, &value);
    pose->position = value.head<2>();
    pose->yaw = value.z();
  }
  void Read(const std::string& key, std::optional<Eigen::Matrix<double, 6, 1>>* value) {
    if (!reader_.Has(key)) return;
    Eigen::Matrix<double, 6, 1> read;
    reader_.Read(key, &read);
    *value = read;
  }
  void Read(const std::string& key, std::vector<Eigen::Vector2d>* points) {
    reader_.Read(key, points);
    reader_.Check(key, points->size() <= 10000, "has more than 10000 points");
  }

  common::YamlReader reader_;
};

// Writes every key with its value (the resolved scenario a run leaves beside its outputs).
class WriteArchive {
 public:
  template <typename T>
  void Field(const std::string& key, T* value) {
    node_[key] = *value;
  }
  template <typename T>
  void Field(const std::string& key, T* value, const Bounds&) {
    Field(key, value);
  }
  void Field(const std::string& key, Eigen::Vector3d* value) {
    WriteFlow(key, {value->x(), value->y(), value->z()});
  }
  void Field(const std::string& key, Eigen::Vector2d* value) {
    WriteFlow(key, {value->x(), value->y()});
  }
  void Field(const std::string& key, std::array<double, 2>* range) {
    WriteFlow(key, {range->at(0), range->at(1)});
  }
  void Field(const std::string& key, common::Pose2* pose) {
    WriteFlow(key, {pose->position.x(), pose->position.y(), pose->yaw});
  }
  void Field(const std::string& key, std::vector<Eigen::Vector2d>* points) {
    YAML::Node sequence(YAML::NodeType::Sequence);
    for (const Eigen::Vector2d& p : *points) {
      YAML::Node point(YAML::NodeType::Sequence);
      point.push_back(p.x());
      point.push_back(p.y());
      point.SetStyle(YAML::EmitterStyle::Flow);
      sequence.push_back(point);
    }
    node_[key] = sequence;
  }
  void Field(const std::string& key, std::optional<Eigen::Matrix<double, 6, 1>>* value) {
    if (value->has_value()) {
      const Eigen::Matrix<double, 6, 1>& v = **value;
      WriteFlow(key, {v[0], v[1], v[2], v[3], v[4], v[5]});
    }
  }
  template <typename E>
  void Enum(const std::string& key, E* value) {
    node_[key] = std::string(common::NameOf(*value));
  }
  void Map(const std::string& key, const std::function<void(WriteArchive&)>& visit) {
    WriteArchive child;
    visit(child);
    node_[key] = child.node_;
  }
  template <typename T>
  void Map(const std::string& key, T* value) {
    Map(key, [value](WriteArchive& child) { value->Serialize(&child); });
  }
  template <typename T>
  void Sequence(const std::string& key, std::vector<T>* items, std::size_t) {
    YAML::Node sequence(YAML::NodeType::Sequence);
    for (T& item : *items) {
      WriteArchive child;
      item.Serialize(&child);
      child.node_.SetStyle(YAML::EmitterStyle::Flow);
      sequence.push_back(child.node_);
    }
    node_[key] = sequence;
  }
  const YAML::Node& node() const { return node_; }

 private:
  void WriteFlow(const std::string& key, const std::vector<double>& values) {
    YAML::Node sequence(YAML::NodeType::Sequence);
    for (double v : values) sequence.push_back(v);
    sequence.SetStyle(YAML::EmitterStyle::Flow);
    node_[key] = sequence;
  }
  YAML::Node node_{YAML::NodeType::Map};
};

// Collects every key path a scenario can hold, with the bounds of the numeric ones: the docs'
// bounds table and the check that docs/scenario-format.md names every key. "[i]" stands for any
// item of a sequence.
class KeysArchive {
 public:
  KeysArchive(std::string prefix, std::map<std::string, std::optional<Bounds>>* keys)
      : prefix_(std::move(prefix)), keys_(keys) {}

  template <typename T>
  void Field(const std::string& key, T*) {
    keys_->emplace(prefix_ + key, std::nullopt);
  }
  template <typename T>
  void Field(const std::string& key, T*, const Bounds& bounds) {
    (*keys_)[prefix_ + key] = bounds;
  }
  template <typename E>
  void Enum(const std::string& key, E*) {
    keys_->emplace(prefix_ + key, std::nullopt);
  }
  void Map(const std::string& key, const std::function<void(KeysArchive&)>& visit) {
    KeysArchive child(prefix_ + key + ".", keys_);
    visit(child);
  }
  template <typename T>
  void Map(const std::string& key, T* value) {
    Map(key, [value](KeysArchive& child) { value->Serialize(&child); });
  }
  template <typename T>
  void Sequence(const std::string& key, std::vector<T>*, std::size_t) {
    KeysArchive child(prefix_ + key + "[i].", keys_);
    for (T item : KeyExamples<T>()) item.Serialize(&child);
  }

 private:
  std::string prefix_;
  std::map<std::string, std::optional<Bounds>>* keys_;
};

// The layout of a scenario file: each section is a config struct's own keys (its Serialize),
// and the few keys that belong to the run rather than to a module.
template <typename Archive>
void VisitScenario(Archive* a, Scenario* s) {
  int schema_version = 1;
  a->Field("schema_version", &schema_version, {1, 1});
  a->Field("name", &s->name);
  a->Enum("test_fault", &s->test_fault);
  a->Map("terrain", &s->terrain);
  a->Map("robot", [s](Archive& r) {
    r.Field("model", &s->robot_model);
    r.Field("start", &s->start_W, {-1000.0, 1000.0});
    r.Map("skid_steer", &s->skid_steer);
    r.Field("rollover_limit_deg", &s->rollover_limit_deg, {1.0, 180.0});
  });
  a->Map("physics", [s](Archive& p) {
    p.Field("timestep", &s->physics_timestep_s, {1e-4, 0.01});
    p.Field("ground_friction", &s->ground_friction, {0.01, 5.0});
  });
  a->Field("goal", &s->goal_W, {-1000.0, 1000.0});
  a->Field("duration", &s->duration_s, {0.01, 86400.0});
  a->Enum("mode", &s->mode);
  a->Map("track", &s->track);
  a->Map("controller", [s](Archive& c) {
    double rate_hz = 1.0 / s->mpc.control_period_s;
    c.Field("rate", &rate_hz, {5.0, 1000.0});
    s->mpc.control_period_s = 1.0 / rate_hz;
    c.Map("mpc", &s->mpc);
    c.Field("method", &s->controller_method);
  });
  a->Map("planner", [s](Archive& p) {
    s->planner.Serialize(&p);
    p.Field("method", &s->planner_method);
    p.Field("sampling_iterations", &s->sampling_iterations, {1, 1000000});
  });
  a->Sequence("moving_obstacles", &s->movers, 1000);
  a->Map("traffic", &s->traffic);
  a->Map("navigation", [s](Archive& n) {
    s->navigation.Serialize(&n);
    s->pose_noise.Serialize(&n);
  });
  a->Sequence("drive", &s->drive, 10000);
  a->Map("lidar", [s](Archive& l) {
    s->lidar.Serialize(&l);
    l.Field("mount", &s->lidar_mount_B, {-10, 10});
  });
  a->Map("imu", &s->imu);
  a->Map("localization", [s](Archive& l) {
    l.Enum("method", &s->pose_noise.method);
    s->pose_noise.odometry.Serialize(&l);
    s->lidar_odometry.Serialize(&l);
  });
  a->Map("mapping", [s](Archive& m) {
    m.Field("enabled", &s->mapping_enabled);
    m.Field("method", &s->mapper);
    s->mapping.Serialize(&m);
  });
  a->Map("ground_truth", &s->ground_truth);
  a->Map("video", &s->video);
  a->Map("output", [s](Archive& o) {
    o.Field("dir", &s->output_dir);
    o.Field("mcap", &s->mcap);
    o.Field("mcap_map_period", &s->mcap_map_period_s, {0.0, 60.0});
  });
  a->Enum("expect", &s->expected_outcome);
}

// Every key a scenario can hold (each terrain type's parameters included).
std::map<std::string, std::optional<Bounds>> AllKeys() {
  std::map<std::string, std::optional<Bounds>> keys;
  for (const auto& terrain_type : sim::kTerrainTypeNames) {
    Scenario scenario;
    scenario.terrain.type = terrain_type.value;
    KeysArchive archive("", &keys);
    VisitScenario(&archive, &scenario);
  }
  return keys;
}

// The checks across the fields of each section, with the section's key path and the file added.
void ValidateSections(const Scenario& s) {
  using common::ValidateAt;
  ValidateAt("terrain", [&] { sim::ValidateTerrainConfig(s.terrain); });
  ValidateAt("video", [&] { renders::ValidateRenderConfig(s.video.render); });
  ValidateAt("lidar", [&] { lidar::ValidateLidarConfig(s.lidar); });
  ValidateAt("imu", [&] { sim::ValidateImuConfig(s.imu); });
  ValidateAt("controller.mpc", [&] { controller::ValidateMpcConfig(s.mpc); });
  ValidateAt("mapping", [&] { mapping::ValidateFsgpConfig(s.mapping); });
  ValidateAt("planner", [&] { planner::ValidateNavigationPlannerConfig(s.planner); });
  ValidateAt("navigation", [&] {
    planner::ValidateNavigationSettings(s.navigation);
    sim::ValidatePoseNoiseConfig(s.pose_noise);
  });
  ValidateAt("localization", [&] {
    sim::ValidateOdometryDriftConfig(s.pose_noise.odometry);
    mapping::ValidateLidarOdometryConfig(s.lidar_odometry);
    if (s.pose_noise.method == sim::LocalizationMethod::kScanMatching && !s.lidar.enabled) {
      throw common::InputError("", "method",
                               "value scan-matching needs the LiDAR (lidar.enabled: true)");
    }
  });
  ValidateAt("traffic", [&] { sim::ValidateTrafficSettings(s.traffic); });
  ValidateAt("moving_obstacles", [&] { sim::ValidateMovingObstacles(s.movers); });
}

}  // namespace

Scenario LoadScenario(const common::YamlDocument& document) {
  Scenario scenario;
  ReadArchive archive(document.Root());
  VisitScenario(&archive, &scenario);
  archive.Finish();
  LoadTerrainFiles(document.source(), &scenario.terrain);
  try {
    ValidateSections(scenario);
  } catch (const common::InputError& e) {
    throw e.InFile(document.source());
  }
  // the methods by name: built-in or registered (scenarios/run/plugins.h)
  try {
    FindMapper(scenario.mapper);
    FindPathSearch(scenario.planner_method);
    FindController(scenario.controller_method);
  } catch (const common::InputError& e) {
    throw e.InFile(document.source());
  }
  if (scenario.mode == RunMode::kNavigate && !UsesGroundTruthMap(scenario) &&
      !(scenario.lidar.enabled && scenario.mapping_enabled)) {
    throw common::InputError(document.source(), "mapping.method",
                             "mode navigate maps from the LiDAR: enable lidar and mapping, or use "
                             "the 'ground-truth' map");
  }
  // a closed-loop run is expected to reach its goal unless the file says otherwise
  if (scenario.mode == RunMode::kNavigate && !document.Root().Has("expect")) {
    scenario.expected_outcome = Outcome::kSuccess;
  }
  if (scenario.mode == RunMode::kTrack && scenario.track.reference == ReferenceShape::kFile &&
      scenario.track.file.empty()) {
    throw common::InputError(document.source(), "track.file", "required for reference 'file'");
  }
  return scenario;
}

std::string ScenarioBoundsTable() {
  std::ostringstream table;
  table << "| key | min | max |\n|---|---|---|\n";
  for (const auto& [key, bounds] : AllKeys()) {
    if (bounds) table << "| `" << key << "` | " << bounds->min << " | " << bounds->max << " |\n";
  }
  return table.str();
}

std::vector<std::string> ScenarioKeys() {
  std::vector<std::string> keys;
  for (const auto& [key, bounds] : AllKeys()) keys.push_back(key);
  return keys;
}

std::string ResolvedScenarioYaml(const Scenario& scenario) {
  Scenario copy = scenario;
  WriteArchive archive;
  VisitScenario(&archive, &copy);
  YAML::Emitter emitter;
  emitter << archive.node();
  return std::string(emitter.c_str()) + "\n";
}

Eigen::Isometry3d MountPose(const Eigen::Matrix<double, 6, 1>& mount) {
  Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();
  X_BL.translation() = mount.head<3>();
  X_BL.linear() = (Eigen::AngleAxisd(mount[5], Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(mount[4], Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(mount[3], Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  return X_BL;
}

common::Twist2 DriveCommandAt(const std::vector<DriveSegment>& drive, double t_s) {
  double segment_start = 0.0;
  for (const DriveSegment& segment : drive) {
    if (t_s < segment_start + segment.duration_s) return {segment.v_m_s, segment.omega_rad_s};
    segment_start += segment.duration_s;
  }
  return {};
}

void ApplyOverrides(const std::vector<std::string>& assignments, common::YamlDocument* document) {
  for (const std::string& assignment : assignments) {
    const std::size_t equals = assignment.find('=');
    if (equals == std::string::npos || equals == 0) {
      throw common::InputError("--set", assignment, "expected key.path=value");
    }
    document->Set(assignment.substr(0, equals), assignment.substr(equals + 1));
  }
}

const std::string& DefaultScenarioYaml() {
  static const std::string kYaml =
      R"(# trav's built-in default scenario: the Scout Mini crosses 30 m of hilly, wooded ground to a
# goal, mapping it from its own LiDAR scans (FSGP-BGK), planning (A* and trajectory optimisation) and
# tracking the plan with the MPC.
schema_version: 1
name: default
terrain:
  type: forest
  seed: 7
  size: [50, 50]
  resolution: 0.1
  parameters:
    tree_density: 0.03
robot:
  start: [-15, 0, 0]
goal: [15, 0]
duration: 60
mode: navigate
video:
  enabled: true
  width: 1280
  height: 720
  fps: 30
  camera: chase
output:
  dir: out/default
)";
  return kYaml;
}

}  // namespace trav::scenarios
