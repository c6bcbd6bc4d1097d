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

#include "common/enum_names.h"
#include "common/input_error.h"

namespace trav::scenarios {
namespace {

// How a mover moves, as the scenario file names it (the motion variant's alternative).
enum class MotionKind { kWaypoints, kConstantVelocity, kRandomWalk };
inline constexpr std::array<common::EnumName<MotionKind>, 3> kMotionKindNames{
    {{MotionKind::kWaypoints, "waypoints"},
     {MotionKind::kConstantVelocity, "constant_velocity"},
     {MotionKind::kRandomWalk, "random_walk"}}};
constexpr const auto& EnumNames(MotionKind) { return kMotionKindNames; }

// One list of keys drives both loading and writing a scenario (as Drake's Serialize visitors), so
// the loader and the resolved file cannot drift apart.
// The closed range [min, max] a numeric key (each component of a vector key) must lie in, in the
// key's unit. Every numeric key has one (ReadArchive refuses to compile a numeric field without),
// so that no value can run trav out of memory or time or into a non-finite state; docs/
// scenario-format.md lists them (BoundsTable, kept equal by a test).
struct Bounds {
  double min;
  double max;
};

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

// One list of keys drives both loading and writing a scenario (as Drake's Serialize visitors), so
// the loader and the resolved file cannot drift apart.
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
  void Sequence(const std::string& key, std::vector<T>* items, std::size_t max_items,
                const std::function<void(ReadArchive&, T&)>& visit) {
    if (!reader_.Has(key)) return;
    items->clear();
    std::vector<common::YamlReader> readers = reader_.MapSequence(key);
    reader_.Check(key, readers.size() <= max_items,
                  "has " + std::to_string(readers.size()) + " items, more than the " +
                      std::to_string(max_items) + " allowed");
    for (common::YamlReader& item_reader : readers) {
      ReadArchive item(item_reader);
      items->emplace_back();
      visit(item, items->back());
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
  void Sequence(const std::string& key, std::vector<T>* items, std::size_t,
                const std::function<void(WriteArchive&, T&)>& visit) {
    YAML::Node sequence(YAML::NodeType::Sequence);
    for (T& item : *items) {
      WriteArchive child;
      visit(child, item);
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

// Collects the bounds of every numeric key (the table of docs/scenario-format.md).
class BoundsArchive {
 public:
  BoundsArchive(std::string prefix, std::map<std::string, Bounds>* bounds)
      : prefix_(std::move(prefix)), bounds_(bounds) {}

  template <typename T>
  void Field(const std::string&, T*) {}
  template <typename T>
  void Field(const std::string& key, T*, const Bounds& bounds) {
    (*bounds_)[prefix_ + key] = bounds;
  }
  template <typename E>
  void Enum(const std::string&, E*) {}
  void Map(const std::string& key, const std::function<void(BoundsArchive&)>& visit) {
    BoundsArchive child(prefix_ + key + ".", bounds_);
    visit(child);
  }
  template <typename T>
  void Sequence(const std::string& key, std::vector<T>*, std::size_t,
                const std::function<void(BoundsArchive&, T&)>& visit) {
    BoundsArchive child(prefix_ + key + "[i].", bounds_);
    for (T item : Variants<T>()) visit(child, item);
  }

 private:
  // Items that together reach every key of a sequence's items.
  template <typename T>
  static std::vector<T> Variants() {
    if constexpr (std::is_same_v<T, sim::MovingObstacle>) {
      std::vector<T> movers(3);
      movers[0].motion = sim::WaypointMotion{};
      movers[1].motion = sim::ConstantVelocityMotion{};
      movers[2].motion = sim::RandomWalkMotion{};
      return movers;
    } else {
      return {T{}};
    }
  }

  std::string prefix_;
  std::map<std::string, Bounds>* bounds_;
};

template <typename Archive>
void VisitTerrainParameters(Archive& a, sim::TerrainConfig& t) {
  switch (t.type) {
    case sim::TerrainType::kFlat:
      break;
    case sim::TerrainType::kSlope:
      a.Field("angle_deg", &t.slope.angle_deg, {-60, 60});
      a.Field("start_x", &t.slope.start_x_m, {-1000.0, 1000.0});
      break;
    case sim::TerrainType::kStep:
      a.Field("height", &t.step.height_m, {-5, 5});
      a.Field("x", &t.step.x_m, {-1000.0, 1000.0});
      break;
    case sim::TerrainType::kStairs:
      a.Field("step_height", &t.stairs.step_height_m, {0.005, 2});
      a.Field("step_depth", &t.stairs.step_depth_m, {0.05, 20});
      a.Field("num_steps", &t.stairs.num_steps, {1, 1000});
      a.Field("start_x", &t.stairs.start_x_m, {-1000.0, 1000.0});
      break;
    case sim::TerrainType::kRoad:
      a.Field("block_size", &t.road.block_size_m, {5, 500});
      a.Field("street_width", &t.road.street_width_m, {1, 100});
      a.Field("sidewalk_width", &t.road.sidewalk_width_m, {0, 50});
      a.Field("curb_height", &t.road.curb_height_m, {0, 1});
      a.Field("camber", &t.road.camber, {0, 0.5});
      a.Field("poles_per_block", &t.road.poles_per_block, {0, 100});
      break;
    case sim::TerrainType::kIndoor:
      a.Field("min_room_size", &t.indoor.min_room_size_m, {1, 100});
      a.Field("wall_height", &t.indoor.wall_height_m, {0.1, 20});
      a.Field("wall_thickness", &t.indoor.wall_thickness_m, {0.02, 5});
      a.Field("door_width", &t.indoor.door_width_m, {0.2, 50});
      a.Field("furniture_per_room", &t.indoor.furniture_per_room, {0, 50});
      break;
    case sim::TerrainType::kHilly:
    case sim::TerrainType::kForest:
    case sim::TerrainType::kRuin:
      a.Enum("family", &t.hilly.fractal.family);
      a.Field("octaves", &t.hilly.fractal.octaves, {1, 16});
      a.Field("lacunarity", &t.hilly.fractal.lacunarity, {1, 8});
      a.Field("gain", &t.hilly.fractal.gain, {0, 1});
      a.Field("warp", &t.hilly.fractal.warp, {0, 100});
      a.Field("wavelength", &t.hilly.wavelength_m, {0.5, 1000});
      a.Field("slope_p95_deg", &t.hilly.slope_p95_deg, {0, 80});
      a.Field("roughness", &t.hilly.roughness_m, {0, 2});
      a.Field("roughness_cell", &t.hilly.roughness_cell_m, {0.01, 10});
      if (t.type == sim::TerrainType::kForest) {
        a.Field("tree_density", &t.forest.tree_density_per_m2, {0, 0.5});
        a.Field("trunk_radius", &t.forest.trunk_radius_m, {0.01, 2});
        a.Field("trunk_height", &t.forest.trunk_height_m, {0.1, 50});
        a.Field("canopy", &t.forest.canopy);
      }
      if (t.type == sim::TerrainType::kRuin) {
        a.Field("num_boxes", &t.ruin.num_boxes, {0, 2000});
        a.Field("num_columns", &t.ruin.num_columns, {0, 2000});
        a.Field("num_walls", &t.ruin.num_walls, {0, 2000});
        a.Field("num_rubble", &t.ruin.num_rubble, {0, 20000});
        a.Field("burial_fraction_max", &t.ruin.burial_fraction_max, {0, 1});
      }
      break;
  }
}

// One mover: its shape, and the keys of its motion (the variant follows the `motion` key).
template <typename Archive>
void VisitMover(Archive& a, sim::MovingObstacle& m) {
  a.Field("name", &m.name);
  a.Enum("shape", &m.shape);
  a.Field("radius", &m.radius_m, {0.01, 10});
  a.Field("half_height", &m.half_height_m, {0.01, 10});
  a.Field("box_half_extents", &m.box_half_extents_m, {0.01, 10});
  MotionKind kind = std::holds_alternative<sim::WaypointMotion>(m.motion) ? MotionKind::kWaypoints
                    : std::holds_alternative<sim::RandomWalkMotion>(m.motion)
                        ? MotionKind::kRandomWalk
                        : MotionKind::kConstantVelocity;
  a.Enum("motion", &kind);
  switch (kind) {
    case MotionKind::kWaypoints: {
      if (!std::holds_alternative<sim::WaypointMotion>(m.motion)) m.motion = sim::WaypointMotion{};
      auto& w = std::get<sim::WaypointMotion>(m.motion);
      a.Field("waypoints", &w.waypoints_W, {-1000.0, 1000.0});
      a.Field("speed", &w.speed_m_s, {0, 20});
      a.Enum("loop", &w.loop);
      a.Field("start_delay", &w.start_delay_s, {0, 86400});
      a.Field("personal_distance", &m.personal_distance_m, {0, 20});
      break;
    }
    case MotionKind::kConstantVelocity: {
      if (!std::holds_alternative<sim::ConstantVelocityMotion>(m.motion)) {
        m.motion = sim::ConstantVelocityMotion{};
      }
      auto& c = std::get<sim::ConstantVelocityMotion>(m.motion);
      a.Field("start", &c.start_W, {-1000.0, 1000.0});
      a.Field("velocity", &c.velocity_W, {-20, 20});
      a.Field("start_time", &c.start_time_s, {0, 86400});
      break;
    }
    case MotionKind::kRandomWalk: {
      if (!std::holds_alternative<sim::RandomWalkMotion>(m.motion))
        m.motion = sim::RandomWalkMotion{};
      auto& r = std::get<sim::RandomWalkMotion>(m.motion);
      a.Field("seed", &r.seed);
      a.Field("area_centre", &r.area_centre_W, {-1000.0, 1000.0});
      a.Field("area_radius", &r.area_radius_m, {0, 1000.0});
      a.Field("speed", &r.speed_m_s, {0, 20});
      a.Field("pause", &r.pause_s, {0, 3600});
      break;
    }
  }
}

// The keys under `terrain`.
template <typename Archive>
void VisitTerrain(Archive& t, Scenario& s) {
  t.Enum("type", &s.terrain.type);
  t.Field("seed", &s.terrain.seed);
  t.Field("size", &s.terrain.size_m, {2, 500});
  t.Field("resolution", &s.terrain.resolution_m, {0.02, 1.0});
  t.Map("parameters", [&](Archive& p) { VisitTerrainParameters(p, s.terrain); });
  t.template Sequence<sim::PlacedBox>(
      "boxes", &s.terrain.boxes, 10000, [](Archive& b, sim::PlacedBox& box) {
        b.Field("name", &box.name);
        b.Field("centre", &box.centre_W, {-1000.0, 1000.0});
        b.Field("half_extents", &box.half_extents_m, {0.005, 500.0});
        b.Field("height", &box.height_m, {0.005, 100.0});
        b.Field("yaw", &box.yaw_rad, {-10.0, 10.0});
      });
}

// The keys under `robot`.
template <typename Archive>
void VisitRobot(Archive& r, Scenario& s) {
  r.Field("model", &s.robot_model);
  r.Field("start", &s.start_W, {-1000.0, 1000.0});
  r.Map("skid_steer", [&](Archive& k) {
    k.Field("wheel_radius", &s.skid_steer.wheel_radius_m, {0.01, 2.0});
    k.Field("track", &s.skid_steer.track_m, {0.05, 10.0});
    k.Field("effective_track_factor", &s.skid_steer.effective_track_factor, {1.0, 20.0});
    k.Field("max_speed", &s.skid_steer.max_speed_m_s, {0.01, 30.0});
    k.Field("max_yaw_rate", &s.skid_steer.max_yaw_rate_rad_s, {0.01, 30.0});
    k.Field("max_wheel_speed", &s.skid_steer.max_wheel_speed_rad_s, {0.1, 1000.0});
  });
  r.Field("rollover_limit_deg", &s.rollover_limit_deg, {1.0, 180.0});
}

// The keys under `track`.
template <typename Archive>
void VisitTrack(Archive& t, Scenario& s) {
  t.Enum("reference", &s.track.reference);
  t.Field("size", &s.track.size_m, {0.5, 1000.0});
  t.Field("amplitude", &s.track.amplitude_m, {0, 500});
  t.Field("wavelength", &s.track.wavelength_m, {0.5, 1000.0});
  t.Field("speed", &s.track.speed_m_s, {0.01, 10.0});
  t.Field("acceleration", &s.track.acceleration_m_s2, {0.01, 50.0});
  t.Field("file", &s.track.file);
}

// The keys under `controller`.
template <typename Archive>
void VisitController(Archive& c, Scenario& s) {
  double rate_hz = 1.0 / s.mpc.control_period_s;
  c.Field("rate", &rate_hz, {5.0, 1000.0});
  s.mpc.control_period_s = 1.0 / rate_hz;
  c.Map("mpc", [&](Archive& m) {
    controller::MpcConfig& k = s.mpc;
    m.Field("horizon", &k.horizon, {1, 200});
    m.Field("step", &k.step_s, {0.005, 1});
    m.Field("state_weights", &k.state_weights, {0, 1000000.0});
    m.Field("input_weights", &k.input_weights, {0, 1000000.0});
    m.Field("rate_weights", &k.rate_weights, {0, 1000000.0});
    m.Field("max_speed", &k.max_speed_m_s, {0.01, 30});
    m.Field("min_speed", &k.min_speed_m_s, {-30, 0});
    m.Field("max_yaw_rate", &k.max_yaw_rate_rad_s, {0.01, 30});
    m.Field("max_acceleration", &k.max_acceleration_m_s2, {0.01, 100});
    m.Field("max_yaw_acceleration", &k.max_yaw_acceleration_rad_s2, {0.01, 100});
    m.Field("actuator_time_constant", &k.actuator_time_constant_s, {0, 10});
    m.Field("max_iterations", &k.max_iterations, {1, 1000});
  });
}

// The keys under `planner`.
template <typename Archive>
void VisitPlanner(Archive& p, Scenario& s) {
  planner::CostMapConfig& search = s.planner.search;
  p.Map("search", [&](Archive& k) {
    k.Field("cost_weight", &search.cost_weight, {0, 1000000.0});
    k.Field("lethal_threshold", &search.lethal_threshold, {0, 1});
    k.Field("inflation_radius", &search.inflation_radius_m, {0, 5});
    k.Enum("unknown_policy", &search.unknown_policy);
    k.Field("unknown_cost", &search.unknown_cost, {0, 1});
    k.Field("simplify_tolerance", &s.planner.simplify_tolerance, {0, 10});
    k.Field("substitute_goal_reach", &s.planner.substitute_goal_reach_m, {0, 100});
  });
  planner::TrajectoryOptimizerConfig& o = s.planner.optimizer;
  p.Map("optimizer", [&](Archive& k) {
    k.Field("max_speed", &o.limits.max_speed_m_s, {0.01, 30});
    k.Field("max_yaw_rate", &o.limits.max_yaw_rate_rad_s, {0.01, 30});
    k.Field("max_acceleration", &o.limits.max_acceleration_m_s2, {0.01, 100});
    k.Field("max_yaw_acceleration", &o.limits.max_yaw_acceleration_rad_s2, {0.01, 100});
    k.Field("max_centripetal_acceleration", &o.limits.max_centripetal_acceleration_m_s2,
            {0.01, 100});
    k.Field("yaw_jerk_weight", &o.weights.yaw_jerk, {0, 1000000000.0});
    k.Field("arc_length_jerk_weight", &o.weights.arc_length_jerk, {0, 1000000000.0});
    k.Field("time_weight", &o.weights.time, {0, 1000000000.0});
    k.Field("traversability_weight", &o.weights.traversability, {0, 1000000000.0});
    k.Field("limits_weight", &o.weights.limits, {0, 1000000000.0});
    k.Field("clearance_weight", &o.weights.clearance, {0, 1000000000.0});
    k.Field("moving_obstacles_weight", &o.weights.moving_obstacles, {0, 1000000000.0});
    k.Field("clearance", &o.clearance_m, {0, 5});
    k.Field("min_clearance", &o.min_clearance_m, {0, 5});
    k.Field("robot_radius", &o.robot_radius_m, {0, 5});
    k.Field("obstacle_clearance", &o.obstacle_clearance_m, {0, 10});
    k.Field("clearance_growth", &o.clearance_growth_m_s, {0, 10});
    k.Field("piece_length", &o.piece_length_m, {0.1, 100});
    k.Field("samples_per_piece", &o.samples_per_piece, {1, 100});
    k.Field("max_iterations", &o.max_iterations, {1, 100000});
    k.Field("max_rounds", &o.max_rounds, {1, 100});
    k.Field("warm_start", &o.warm_start);
  });
}

// The keys under `traffic`.
template <typename Archive>
void VisitTraffic(Archive& t, Scenario& s) {
  t.Field("count", &s.traffic.count, {0, 200});
  t.Field("speed", &s.traffic.speed_m_s, {0, 5});
  t.Enum("behaviour", &s.traffic.behaviour);
  t.Enum("shape", &s.traffic.shape);
  t.Field("seed", &s.traffic.seed);
  t.Field("area_radius", &s.traffic.area_radius_m, {0, 500});
  t.Field("keep_clear", &s.traffic.keep_clear_m, {0, 100});
}

// The keys under `navigation`.
template <typename Archive>
void VisitNavigation(Archive& n, Scenario& s) {
  planner::NavigationSettings& k = s.navigation;
  n.Field("movers_from_ground_truth", &k.movers_from_ground_truth);
  n.Field("mover_sensing_range", &k.mover_sensing_range_m, {0, 500});
  n.Field("position_noise", &s.pose_noise.position_noise_m, {0, 10});
  n.Field("yaw_noise", &s.pose_noise.yaw_noise_rad, {0, 3.15});
  n.Field("drift", &s.pose_noise.drift_m_per_sqrt_s, {0, 10});
  n.Field("localization_seed", &s.pose_noise.seed);
  n.Field("mapping_latency", &k.mapping_latency_s, {0, 10});
  n.Field("goal_radius", &k.goal_radius_m, {0.01, 100});
  n.Field("planning_rate", &k.planning_rate_hz, {0.1, 100});
  n.Field("replan_deviation", &k.replan_deviation_m, {0.01, 100});
  n.Field("safety_horizon", &k.safety_horizon_s, {0, 60});
  n.Field("stuck_time", &k.stuck_time_s, {0.1, 86400});
  n.Field("stuck_distance", &k.stuck_distance_m, {0, 100});
  n.Field("planning_failure_time", &k.planning_failure_time_s, {0.1, 86400});
  n.Field("near_miss_clearance", &k.near_miss_clearance_m, {0, 10});
}

// The keys under `lidar`.
template <typename Archive>
void VisitLidar(Archive& l, Scenario& s) {
  lidar::LidarConfig& c = s.lidar;
  l.Field("enabled", &c.enabled);
  l.Field("table", &c.pattern_table);
  l.Field("rate", &c.points_per_second, {1, 1000000.0});
  l.Field("frame_period", &c.frame_period_s, {0.005, 1});
  l.Field("range_min", &c.range_min_m, {0, 10});
  l.Field("range_max", &c.range_max_m, {0.1, 500});
  l.Field("range_noise", &c.range_noise_m, {0, 1});
  l.Field("angular_noise_deg", &c.angular_noise_deg, {0, 10});
  l.Field("dropout", &c.dropout, {0, 0.99});
  l.Field("occlusion", &c.occlusion, {0, 0.99});
  l.Field("occlusion_sectors", &c.occlusion_sectors, {1, 360});
  l.Field("seed", &c.seed);
  l.Field("threads", &c.threads, {1, 64});
  l.Field("mount", &s.lidar_mount_B, {-10, 10});
}

// The keys under `mapping`.
template <typename Archive>
void VisitMapping(Archive& mp, Scenario& s) {
  mapping::FsgpConfig& c = s.mapping;
  mp.Field("enabled", &s.mapping_enabled);
  mp.Enum("method", &s.mapper);
  mp.Field("window", &c.area.window_m, {1, 100});
  mp.Field("resolution", &c.area.resolution_m, {0.02, 2});
  mp.Field("map_size", &c.area.map_size_m, {1, 1000});
  mp.Field("max_height_above_robot", &c.area.max_height_above_robot_m, {0, 100});
  mp.Field("max_height_above_ground", &c.max_height_above_ground_m, {0, 100});
  mp.Field("pre_voxel", &c.pre_voxel_m, {0, 1});
  mp.Field("neighbours", &c.neighbours, {3, 200});
  mp.Field("curvature_threshold", &c.curvature_threshold, {0, 10});
  mp.Field("gradient_threshold", &c.gradient_threshold_m, {0, 10});
  mp.Field("feature_voxel", &c.feature_voxel_m, {0, 2});
  mp.Field("max_training_points", &c.max_training_points, {1, 3000});
  mp.Field("seed", &c.seed);
  mp.Field("pca", &c.pca);
  mp.Map("gp", [&](Archive& gp) {
    gp.Enum("kernel", &c.gp.kernel);
    Eigen::Vector4d& l = c.gp.length_scales;
    Eigen::Vector2d xy(l[0], l[1]), features(l[2], l[3]);
    gp.Field("length_scales_xy", &xy, {0.01, 100});
    gp.Field("length_scales_features", &features, {0.0001, 10000.0});
    l << xy, features;
    gp.Field("signal_variance_ratio", &c.gp.signal_variance_ratio, {1e-06, 1000.0});
    gp.Field("noise_std", &c.gp.noise_std_m, {1e-05, 10});
    gp.Field("rq_alpha", &c.gp.rq_alpha, {0.01, 100});
  });
  mp.Field("lbfgs_iterations", &c.lbfgs_iterations, {0, 1000});
  mp.Field("idw_neighbours", &c.idw_neighbours, {1, 100});
  mp.Field("support_radius", &c.support_radius_m, {0.01, 20});
  mp.Field("variance_stride", &c.variance_stride, {1, 100});
  mp.Field("weight_curvature", &c.weight_curvature, {0, 100});
  mp.Field("weight_gradient", &c.weight_gradient, {0, 100});
  mp.Field("weight_slope", &c.weight_slope, {0, 100});
  mp.Field("curvature_max", &c.curvature_max, {1e-06, 100});
  mp.Field("gradient_max", &c.gradient_max_m, {1e-06, 100});
  mp.Field("slope_max", &c.slope_max_rad, {0.001, 1.6});
  mp.Field("fuse", &c.fuse);
  mp.Field("decay_rate", &c.decay_rate, {0, 100});
  mp.Field("variance_epsilon", &c.variance_epsilon, {1e-09, 10});
  mp.Field("smoothing_sigma", &c.smoothing_sigma_m, {0, 5});
  mp.Field("smoothing_radius", &c.smoothing_radius_m, {0, 10});
  mp.Field("accumulate_frames", &c.accumulate_frames, {1, 100});
}

// The keys under `video`.
template <typename Archive>
void VisitVideo(Archive& v, Scenario& s) {
  v.Field("enabled", &s.video.enabled);
  v.Field("width", &s.video.render.width, {16, 4096});
  v.Field("height", &s.video.render.height, {16, 4096});
  v.Field("fps", &s.video.fps, {1.0, 120.0});
  v.Enum("camera", &s.video.camera);
  v.Enum("backend", &s.video.render.backend);
  v.Field("shadows", &s.video.render.shadows);
  v.Field("msaa", &s.video.render.msaa_samples, {0, 16});
}

template <typename Archive>
void VisitScenario(Archive& a, Scenario& s) {
  int schema_version = 1;
  a.Field("schema_version", &schema_version, {1, 1});
  a.Field("name", &s.name);
  a.Enum("test_fault", &s.test_fault);
  a.Map("terrain", [&](Archive& t) { VisitTerrain(t, s); });
  a.Map("robot", [&](Archive& r) { VisitRobot(r, s); });
  a.Map("physics", [&](Archive& p) {
    p.Field("timestep", &s.physics_timestep_s, {1e-4, 0.01});
    p.Field("ground_friction", &s.ground_friction, {0.01, 5.0});
  });
  a.Field("goal", &s.goal_W, {-1000.0, 1000.0});
  a.Field("duration", &s.duration_s, {0.01, 86400.0});
  a.Enum("mode", &s.mode);
  a.Map("track", [&](Archive& t) { VisitTrack(t, s); });
  a.Map("controller", [&](Archive& c) { VisitController(c, s); });
  a.Map("planner", [&](Archive& p) { VisitPlanner(p, s); });
  a.template Sequence<sim::MovingObstacle>("moving_obstacles", &s.movers, 1000,
                                           VisitMover<Archive>);
  a.Map("traffic", [&](Archive& t) { VisitTraffic(t, s); });
  a.Map("navigation", [&](Archive& n) { VisitNavigation(n, s); });
  a.template Sequence<DriveSegment>("drive", &s.drive, 10000,
                                    [](Archive& d, DriveSegment& segment) {
                                      d.Field("v", &segment.v_m_s, {-30, 30});
                                      d.Field("omega", &segment.omega_rad_s, {-30, 30});
                                      d.Field("duration", &segment.duration_s, {0.001, 86400.0});
                                    });
  a.Map("lidar", [&](Archive& l) { VisitLidar(l, s); });
  a.Map("mapping", [&](Archive& mp) { VisitMapping(mp, s); });
  a.Map("ground_truth", [&](Archive& gt) {
    gt.Field("neighbourhood_radius", &s.ground_truth.neighbourhood_radius_m, {0.01, 5.0});
    gt.Field("clearance", &s.ground_truth.clearance_m, {0.01, 5.0});
    gt.Field("footprint_radius", &s.ground_truth.footprint_radius_m, {0.01, 5.0});
  });
  a.Map("video", [&](Archive& v) { VisitVideo(v, s); });
  a.Map("output", [&](Archive& o) { o.Field("dir", &s.output_dir); });
  a.Enum("expect", &s.expected_outcome);
}

}  // namespace

Scenario LoadScenario(const common::YamlDocument& document) {
  Scenario scenario;
  ReadArchive archive(document.Root());
  VisitScenario(archive, scenario);
  archive.Finish();
  // checks across fields, reported with the source file
  try {
    sim::ValidateTerrainConfig(scenario.terrain);
    renders::ValidateRenderConfig(scenario.video.render);
    lidar::ValidateLidarConfig(scenario.lidar);
    controller::ValidateMpcConfig(scenario.mpc);
    mapping::ValidateFsgpConfig(scenario.mapping);
    planner::ValidateNavigationPlannerConfig(scenario.planner);
    planner::ValidateNavigationSettings(scenario.navigation);
    sim::ValidatePoseNoiseConfig(scenario.pose_noise);
    sim::ValidateTrafficSettings(scenario.traffic);
    sim::ValidateMovingObstacles(scenario.movers);
  } catch (const common::InputError& e) {
    throw common::InputError(document.source() + ": " + e.what());
  }
  if (scenario.mode == RunMode::kNavigate && scenario.mapper != MapperMethod::kGroundTruth &&
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
  std::map<std::string, Bounds> bounds;
  for (const auto& terrain_type : sim::kTerrainTypeNames) {
    Scenario scenario;
    scenario.terrain.type = terrain_type.value;
    BoundsArchive archive("", &bounds);
    VisitScenario(archive, scenario);
  }
  std::ostringstream table;
  table << "| key | min | max |\n|---|---|---|\n";
  for (const auto& [key, range] : bounds) {
    table << "| `" << key << "` | " << range.min << " | " << range.max << " |\n";
  }
  return table.str();
}

std::string ResolvedScenarioYaml(const Scenario& scenario) {
  Scenario copy = scenario;
  WriteArchive archive;
  VisitScenario(archive, copy);
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
  width: 640
  height: 480
  fps: 30
  camera: chase
output:
  dir: out/default
)";
  return kYaml;
}

}  // namespace trav::scenarios
