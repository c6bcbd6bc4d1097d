#include "scenarios/run/mcap_recorder.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <utility>
#include <vector>

#include <mcap/writer.hpp>
#include <nlohmann/json.hpp>

#include "common/enum_names.h"
#include "common/pose.h"
#include "scenarios/run/foxglove_schemas.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/recorders.h"

namespace trav::scenarios {
namespace {

using nlohmann::json;

constexpr char kWorldFrame[] = "world";
constexpr char kOdomFrame[] = "odom";
constexpr char kBaseFrame[] = "base_link";
constexpr char kLidarFrame[] = "lidar";
// Lines drawn over the ground by this much, so that the terrain does not hide them [m].
constexpr double kLineLift_m = 0.05;
// foxglove.PackedElementField's numeric type FLOAT32, foxglove.Log's levels, LinePrimitive's
// LINE_STRIP.
constexpr int kFloat32 = 7;
constexpr int kLogInfo = 2;
constexpr int kLogWarning = 3;
constexpr int kLineStrip = 0;

// The schema of /timings: one number per timed module (kTimedModules) and the time.
json ModuleTimesSchema() {
  json properties = {{"t", {{"type", "number"}, {"description", "simulation time [s]"}}}};
  for (const char* module : kTimedModules) {
    properties[std::string(module) + "_ms"] = {
        {"type", "number"}, {"description", "wall time since the previous message [ms]"}};
  }
  return {{"title", "trav.ModuleTimes"}, {"type", "object"}, {"properties", properties}};
}

// RFC 4648 base64, which Foxglove's JSON schemas require for `bytes` fields (contentEncoding
// base64). Written here: none of trav's dependencies exposes an encoder.
std::string Base64(const std::uint8_t* data, std::size_t size) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve(4 * ((size + 2) / 3));
  std::size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const std::uint32_t v = (data[i] << 16) | (data[i + 1] << 8) | data[i + 2];
    for (int shift : {18, 12, 6, 0}) out.push_back(kAlphabet[(v >> shift) & 0x3f]);
  }
  if (i < size) {
    const bool two = i + 1 < size;
    const std::uint32_t v = (data[i] << 16) | (two ? data[i + 1] << 8 : 0);
    out.push_back(kAlphabet[(v >> 18) & 0x3f]);
    out.push_back(kAlphabet[(v >> 12) & 0x3f]);
    out.push_back(two ? kAlphabet[(v >> 6) & 0x3f] : '=');
    out.push_back('=');
  }
  return out;
}

std::uint64_t Nanoseconds(double t_s) {
  return static_cast<std::uint64_t>(std::llround(std::max(0.0, t_s) * 1e9));
}

json Time(double t_s) {
  const std::uint64_t ns = Nanoseconds(t_s);
  return {{"sec", ns / 1000000000}, {"nsec", ns % 1000000000}};
}

json Vector3(const Eigen::Vector3d& v) { return {{"x", v.x()}, {"y", v.y()}, {"z", v.z()}}; }

json Quaternion(const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  return {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}};
}

json Pose(const Eigen::Isometry3d& X) {
  return {{"position", Vector3(X.translation())}, {"orientation", Quaternion(X.linear())}};
}

json Color(double r, double g, double b, double a = 1.0) {
  return {{"r", r}, {"g", g}, {"b", b}, {"a", a}};
}

json Transform(double t_s, const char* parent, const char* child, const Eigen::Isometry3d& X) {
  return {{"timestamp", Time(t_s)},
          {"parent_frame_id", parent},
          {"child_frame_id", child},
          {"translation", Vector3(X.translation())},
          {"rotation", Quaternion(X.linear())}};
}

// A foxglove.SceneEntity with every primitive list present and empty.
json Entity(double t_s, const char* frame, const std::string& id) {
  json entity = {{"timestamp", Time(t_s)}, {"frame_id", frame},     {"id", id},
                 {"lifetime", Time(0.0)},  {"frame_locked", false}, {"metadata", json::array()}};
  for (const char* list :
       {"arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models"}) {
    entity[list] = json::array();
  }
  return entity;
}

// A line strip through `points` (x, y, z) of one colour.
json LineStrip(const std::vector<Eigen::Vector3d>& points, const json& color, double thickness_m) {
  json line = {{"type", kLineStrip},       {"pose", Pose(Eigen::Isometry3d::Identity())},
               {"thickness", thickness_m}, {"scale_invariant", false},
               {"points", json::array()},  {"color", color},
               {"colors", json::array()},  {"indices", json::array()}};
  for (const Eigen::Vector3d& p : points) line["points"].push_back(Vector3(p));
  return line;
}

// A foxglove.SceneUpdate replacing the entity of the topic.
json SceneUpdate(json entity) {
  return {{"deletions", json::array()}, {"entities", json::array({std::move(entity)})}};
}

}  // namespace

struct McapRecorder::Log {
  // The file through a checked stream, so that a full disk is an error (CheckWritten).
  class File : public mcap::IWritable {
   public:
    explicit File(const std::string& path) : stream_(path, std::ios::binary) {}
    void end() override { stream_.close(); }
    uint64_t size() const override { return size_; }
    bool ok() const { return !stream_.fail(); }

   protected:
    void handleWrite(const std::byte* data, uint64_t size) override {
      stream_.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
      size_ += size;
    }

   private:
    std::ofstream stream_;
    uint64_t size_{0};
  };

  explicit Log(const std::string& file_path) : path(file_path), file(file_path) {
    mcap::McapWriterOptions options("");
    options.compression = mcap::Compression::Zstd;
    writer.open(file, options);
  }

  void AddChannel(const std::string& topic, const std::string& schema_name,
                  const std::string& schema) {
    auto found = schema_ids.find(schema_name);
    if (found == schema_ids.end()) {
      mcap::Schema record(schema_name, "jsonschema", schema);
      writer.addSchema(record);
      found = schema_ids.emplace(schema_name, record.id).first;
    }
    mcap::Channel channel(topic, "json", found->second);
    writer.addChannel(channel);
    channels[topic] = Channel{channel.id, 0};
  }

  bool Has(const std::string& topic) const { return channels.count(topic) > 0; }

  // Writes `message`; with `data` its field "data" (base64: nothing to escape) is appended to
  // the text rather than passed through the JSON writer, which would scan and copy it again.
  void Write(const std::string& topic, double t_s, const json& message,
             const std::string* data = nullptr) {
    Channel& channel = channels.at(topic);
    std::string text = message.dump();
    if (data != nullptr) {
      text.pop_back();  // the closing brace
      text.append(",\"data\":\"").append(*data).append("\"}");
    }
    mcap::Message record;
    record.channelId = channel.id;
    record.sequence = channel.sequence++;
    record.logTime = record.publishTime = Nanoseconds(t_s);
    record.data = reinterpret_cast<const std::byte*>(text.data());
    record.dataSize = text.size();
    written_ok = written_ok && writer.write(record).ok();
  }

  void Status(double t_s, int level, const std::string& message) {
    Write("/status", t_s,
          {{"timestamp", Time(t_s)},
           {"level", level},
           {"message", message},
           {"name", "trav"},
           {"file", ""},
           {"line", 0}});
  }

  struct Channel {
    mcap::ChannelId id{0};
    std::uint32_t sequence{0};
  };
  std::string path;
  File file;
  mcap::McapWriter writer;
  std::map<std::string, mcap::SchemaId> schema_ids;
  std::map<std::string, Channel> channels;
  std::map<std::string, double> module_totals_ms;
  bool written_ok{true};
  int horizon_solves{0};   // MPC solves whose horizon is written
  double next_map_s{0.0};  // the first map update from this time is written [s]
  Eigen::Isometry3d X_BL{Eigen::Isometry3d::Identity()};  // the LiDAR's mount
};

namespace {

// Points of a plan on the ground: (x, y) with the ground's height plus a lift.
std::vector<Eigen::Vector3d> OnGround(const sim::TerrainWorld& world,
                                      const std::vector<Eigen::Vector2d>& points_xy) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(points_xy.size());
  for (const Eigen::Vector2d& p : points_xy) {
    points.emplace_back(p.x(), p.y(), world.GroundHeight(p) + kLineLift_m);
  }
  return points;
}

// Movers as discs (cylinders as tall as the robot) with an arrow along their velocity.
json MoversUpdate(double t_s, const char* frame, const std::string& id,
                  const std::vector<planner::MovingObstacle>& movers,
                  const sim::TerrainWorld& world, const json& color) {
  constexpr double kHeight_m = 1.0;
  json entity = Entity(t_s, frame, id);
  for (const planner::MovingObstacle& mover : movers) {
    const double ground_z = world.GroundHeight(mover.position_W);
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() << mover.position_W, ground_z + 0.5 * kHeight_m;
    const double d = 2.0 * mover.radius_m;
    entity["cylinders"].push_back({{"pose", Pose(X)},
                                   {"size", Vector3({d, d, kHeight_m})},
                                   {"bottom_scale", 1.0},
                                   {"top_scale", 1.0},
                                   {"color", color}});
    const double speed = mover.velocity_W.norm();
    if (speed < 1e-3) continue;
    Eigen::Isometry3d X_arrow = Eigen::Isometry3d::Identity();
    X_arrow.translation() << mover.position_W, ground_z + kHeight_m;
    X_arrow.linear() = Eigen::AngleAxisd(std::atan2(mover.velocity_W.y(), mover.velocity_W.x()),
                                         Eigen::Vector3d::UnitZ())
                           .toRotationMatrix();
    entity["arrows"].push_back({{"pose", Pose(X_arrow)},
                                {"shaft_length", speed},
                                {"shaft_diameter", 0.05},
                                {"head_length", 0.15},
                                {"head_diameter", 0.12},
                                {"color", color}});
  }
  return SceneUpdate(std::move(entity));
}

// The map's layers as float32 fields, cell (ix, iy) at row iy, column ix; the data, base64, in
// `data`.
json MapGrid(double t_s, const common::GridLayers& map, std::string* data_base64) {
  const common::GridGeometry& g = map.geometry();
  const std::vector<std::string> names = map.LayerNames();
  const std::size_t cell_bytes = 4 * names.size();
  std::vector<std::uint8_t> data(cell_bytes * static_cast<std::size_t>(g.num_x) * g.num_y);
  json fields = json::array();
  for (std::size_t l = 0; l < names.size(); ++l) {
    fields.push_back({{"name", names[l]}, {"offset", 4 * l}, {"type", kFloat32}});
    const Eigen::MatrixXf& layer = map.Layer(names[l]);
    for (int iy = 0; iy < g.num_y; ++iy) {
      for (int ix = 0; ix < g.num_x; ++ix) {
        const std::size_t cell = static_cast<std::size_t>(iy) * g.num_x + ix;
        std::memcpy(&data[cell * cell_bytes + 4 * l], &layer(ix, iy), 4);
      }
    }
  }
  *data_base64 = Base64(data.data(), data.size());
  Eigen::Isometry3d X_corner = Eigen::Isometry3d::Identity();
  X_corner.translation().head<2>() = g.origin_W - Eigen::Vector2d::Constant(0.5 * g.resolution_m);
  return {{"timestamp", Time(t_s)},
          {"frame_id", kOdomFrame},
          {"pose", Pose(X_corner)},
          {"column_count", g.num_x},
          {"cell_size", {{"x", g.resolution_m}, {"y", g.resolution_m}}},
          {"row_stride", cell_bytes * g.num_x},
          {"cell_stride", cell_bytes},
          {"fields", fields}};
}

}  // namespace

McapRecorder::McapRecorder(const ClosedLoop& loop, const std::string& output_dir)
    : log_(std::make_unique<Log>(output_dir + "/" + kMcapFileName)) {
  Log& log = *log_;
  log.X_BL = loop.lidar_mount_B();
  log.AddChannel("/tf", "foxglove.FrameTransforms", foxglove_schemas::kFrameTransforms);
  log.AddChannel("/status", "foxglove.Log", foxglove_schemas::kLog);
  log.AddChannel("/goal", "foxglove.SceneUpdate", foxglove_schemas::kSceneUpdate);
  if (loop.scenario().lidar.enabled) {
    log.AddChannel("/lidar/points", "foxglove.PointCloud", foxglove_schemas::kPointCloud);
  }
  if (loop.has_mapper()) log.AddChannel("/map", "foxglove.Grid", foxglove_schemas::kGrid);
  if (loop.navigator() != nullptr) {
    for (const char* topic : {"/planner/path", "/planner/trajectory", "/movers/true"}) {
      log.AddChannel(topic, "foxglove.SceneUpdate", foxglove_schemas::kSceneUpdate);
    }
    if (loop.perceives_movers()) {
      log.AddChannel("/movers/perceived", "foxglove.SceneUpdate", foxglove_schemas::kSceneUpdate);
    }
    log.AddChannel("/timings", "trav.ModuleTimes", ModuleTimesSchema().dump());
  }
  if (loop.navigator() != nullptr || loop.tracker() != nullptr) {
    log.AddChannel("/controller/horizon", "foxglove.SceneUpdate", foxglove_schemas::kSceneUpdate);
  }

  const double t_s = loop.state().time_s;
  log.Status(t_s, kLogInfo,
             "start: terrain " + std::string(common::NameOf(loop.scenario().terrain.type)) +
                 " seed " + std::to_string(loop.scenario().terrain.seed));
  json goal = Entity(t_s, kWorldFrame, "goal");
  if (loop.navigator() != nullptr) {
    const Eigen::Vector2d& g = loop.scenario().goal_W;
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() << g, loop.world().GroundHeight(g) + 0.25;
    const double d = 2.0 * loop.scenario().navigation.goal_radius_m;
    goal["spheres"].push_back(
        {{"pose", Pose(X)}, {"size", Vector3({d, d, 0.5})}, {"color", Color(0.1, 0.8, 0.2, 0.6)}});
  }
  log.Write("/goal", t_s, SceneUpdate(std::move(goal)));
}

McapRecorder::~McapRecorder() = default;

void McapRecorder::OnCommand(const ClosedLoop& loop) {
  Log& log = *log_;
  const double t_s = loop.state().time_s;
  const controller::TrajectoryTracker* tracker =
      loop.navigator() != nullptr ? &loop.navigator()->tracker() : loop.tracker();
  if (loop.navigator() != nullptr && loop.navigator_tick().replan != planner::ReplanReason::kNone) {
    const planner::Navigator& navigator = *loop.navigator();
    json path = Entity(t_s, kOdomFrame, "path");
    path["lines"].push_back(
        LineStrip(OnGround(loop.world(), navigator.waypoints_W()), Color(0.2, 0.4, 1.0), 0.04));
    log.Write("/planner/path", t_s, SceneUpdate(std::move(path)));
    std::vector<Eigen::Vector2d> samples;
    const common::Trajectory& trajectory = navigator.trajectory();
    if (!trajectory.empty()) {
      for (double t = trajectory.start_time(); t < trajectory.end_time(); t += 0.1) {
        samples.push_back(trajectory.Sample(t).position_W);
      }
      samples.push_back(trajectory.Sample(trajectory.end_time()).position_W);
    }
    json plan = Entity(t_s, kOdomFrame, "trajectory");
    plan["lines"].push_back(
        LineStrip(OnGround(loop.world(), samples), Color(1.0, 0.55, 0.0), 0.06));
    log.Write("/planner/trajectory", t_s, SceneUpdate(std::move(plan)));
    log.Status(t_s, kLogInfo,
               std::string("plan (") + common::NameOf(loop.navigator_tick().replan) +
                   "): " + navigator.statistics().last_status);
  }
  if (tracker != nullptr && tracker->solves() > log.horizon_solves) {
    log.horizon_solves = tracker->solves();
    const Eigen::Matrix3Xd& states = tracker->predicted_states_W();
    std::vector<Eigen::Vector2d> points;
    for (Eigen::Index k = 0; k < states.cols(); ++k) points.emplace_back(states.col(k).head<2>());
    json horizon = Entity(t_s, kOdomFrame, "horizon");
    horizon["lines"].push_back(
        LineStrip(OnGround(loop.world(), points), Color(0.9, 0.1, 0.9), 0.03));
    log.Write("/controller/horizon", t_s, SceneUpdate(std::move(horizon)));
  }
}

void McapRecorder::OnLidarFrame(const ClosedLoop& /*loop*/, const lidar::LidarFrame& frame,
                                const Eigen::Matrix3Xf& points_W) {
  const common::PointCloud& cloud = frame.points_L;
  constexpr std::size_t kStride = 20;  // x, y, z, intensity, time: float32 each
  std::vector<std::uint8_t> data(kStride * static_cast<std::size_t>(points_W.cols()));
  for (Eigen::Index i = 0; i < points_W.cols(); ++i) {
    const float values[5] = {
        points_W(0, i), points_W(1, i), points_W(2, i),
        cloud.reflectivity.size() > 0 ? static_cast<float>(cloud.reflectivity[i]) : 0.0f,
        cloud.time_offsets.size() > 0 ? cloud.time_offsets[i] : 0.0f};
    std::memcpy(&data[kStride * static_cast<std::size_t>(i)], values, kStride);
  }
  json fields = json::array();
  const char* names[5] = {"x", "y", "z", "intensity", "time"};
  for (int f = 0; f < 5; ++f) {
    fields.push_back({{"name", names[f]}, {"offset", 4 * f}, {"type", kFloat32}});
  }
  const std::string data_base64 = Base64(data.data(), data.size());
  log_->Write("/lidar/points", cloud.stamp_s,
              {{"timestamp", Time(cloud.stamp_s)},
               {"frame_id", kWorldFrame},
               {"pose", Pose(Eigen::Isometry3d::Identity())},
               {"point_stride", kStride},
               {"fields", fields}},
              &data_base64);
}

void McapRecorder::OnMapUpdate(const ClosedLoop& loop) {
  Log& log = *log_;
  const double t_s = loop.state().time_s;
  if (t_s < log.next_map_s - 1e-9) return;
  log.next_map_s = t_s + loop.scenario().mcap_map_period_s;
  std::string data_base64;
  const json grid = MapGrid(t_s, *loop.map(), &data_base64);
  log.Write("/map", t_s, grid, &data_base64);
}

void McapRecorder::OnPhysicsStep(const ClosedLoop& loop, const LoopStep& step) {
  if (!TrajectorySampleDue(loop, step.index)) return;
  const double t_s = step.state.time_s;
  const Eigen::Isometry3d& X_WB = step.state.X_WB;
  const Eigen::Isometry3d X_WO = loop.OdometryFromWorld().inverse();
  json transforms = json::array({Transform(t_s, kWorldFrame, kBaseFrame, X_WB),
                                 Transform(t_s, kWorldFrame, kOdomFrame, X_WO)});
  if (loop.scenario().lidar.enabled) {
    transforms.push_back(Transform(t_s, kBaseFrame, kLidarFrame, log_->X_BL));
  }
  log_->Write("/tf", t_s, {{"transforms", transforms}});
}

void McapRecorder::OnStepChecked(const ClosedLoop& loop, const LoopStep& step) {
  if (loop.navigator() == nullptr || !TimeSeriesSampleDue(loop, step.index)) return;
  Log& log = *log_;
  const double t_s = step.state.time_s;
  json times = {{"t", t_s}};
  for (const char* module : kTimedModules) {
    const double total = loop.times().Total(module);
    times[std::string(module) + "_ms"] = total - log.module_totals_ms[module];
    log.module_totals_ms[module] = total;
  }
  log.Write("/timings", t_s, times);
  log.Write("/movers/true", t_s,
            MoversUpdate(t_s, kWorldFrame, "movers", loop.true_movers(), loop.world(),
                         Color(0.95, 0.55, 0.1, 0.8)));
  if (log.Has("/movers/perceived")) {
    log.Write("/movers/perceived", t_s,
              MoversUpdate(t_s, kOdomFrame, "perceived", loop.predicted_movers(), loop.world(),
                           Color(0.2, 0.8, 1.0, 0.5)));
  }
}

void McapRecorder::OnEnd(const ClosedLoop& loop, Outcome outcome) {
  Log& log = *log_;
  const bool success = outcome == Outcome::kSuccess || outcome == Outcome::kCompleted;
  log.Status(loop.state().time_s, success ? kLogInfo : kLogWarning,
             std::string("outcome: ") + common::NameOf(outcome));
  log.writer.close();
  CheckWritten(log.path, log.written_ok && log.file.ok());
}

}  // namespace trav::scenarios
