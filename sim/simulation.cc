#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <unordered_map>

#include <mujoco/mujoco.h>

#include "common/input_error.h"
#include "common/input_file.h"
#include "common/logging.h"

namespace trav::sim {
namespace {

static_assert(mjNWARNING == 8, "Simulation keeps one counter per MuJoCo warning kind");

constexpr const char* kWheelJoints[4] = {"front_left_wheel", "rear_left_wheel", "front_right_wheel",
                                         "rear_right_wheel"};
constexpr const char* kWheelActuators[4] = {"front_left_motor", "rear_left_motor",
                                            "front_right_motor", "rear_right_motor"};
// Wheel contact points in B at rest (x, y) and the wheel radius [m]; must match scout_mini.xml.
constexpr double kWheelX_m = 0.2255;
constexpr double kWheelY_m = 0.245;
constexpr double kWheelRadius_m = 0.0875;
constexpr double kDropHeight_m = 0.01;

// The pose in W of a MuJoCo frame from its position and row-major rotation matrix.
Eigen::Isometry3d FramePose(const mjtNum* position, const mjtNum* rotation) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Map<const Eigen::Vector3d>(position);
  X.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(rotation);
  return X;
}

const char* WarningName(int kind) {
  switch (kind) {
    case mjWARN_INERTIA:
      return "near-singular inertia";
    case mjWARN_CONTACTFULL:
      return "contact list full";
    case mjWARN_CNSTRFULL:
      return "constraint list full";
    case mjWARN_VGEOMFULL:
      return "visual geom list full";
    case mjWARN_BADQPOS:
      return "bad number in qpos";
    case mjWARN_BADQVEL:
      return "bad number in qvel";
    case mjWARN_BADQACC:
      return "bad number in qacc";
    case mjWARN_BADCTRL:
      return "bad number in ctrl";
    default:
      return "unknown warning";
  }
}

void ThrowMujocoError(const char* message) {
  throw std::runtime_error(std::string("MuJoCo error: ") + message);
}

void LogMujocoWarning(const char* message) {
  common::Log(common::LogLevel::kDebug, std::string("MuJoCo warning: ") + message);
}

// Top of a primitive's bounding box in W [m].
double TopOf(const common::Primitive& primitive) {
  const Eigen::Matrix3d& R = primitive.X_WO.linear();
  const Eigen::Vector3d& size = primitive.size;
  const double axis_z = std::abs(R(2, 2));  // vertical component of the local z axis
  const double across = std::sqrt(std::max(0.0, 1.0 - axis_z * axis_z));
  double extent = 0.0;
  switch (primitive.shape) {
    case ShapeType::kBox:
      extent = std::abs(R(2, 0)) * size.x() + std::abs(R(2, 1)) * size.y() + axis_z * size.z();
      break;
    case ShapeType::kCylinder:
      extent = axis_z * size.y() + across * size.x();
      break;
    case ShapeType::kCapsule:
      extent = axis_z * size.y() + size.x();
      break;
    case ShapeType::kSphere:
      extent = size.x();
      break;
  }
  return primitive.X_WO.translation().z() + extent;
}

// MuJoCo's virtual file system, freed with its owner.
struct ScopedVfs {
  ScopedVfs() { mj_defaultVFS(&vfs); }
  ~ScopedVfs() { mj_deleteVFS(&vfs); }
  ScopedVfs(const ScopedVfs&) = delete;
  ScopedVfs& operator=(const ScopedVfs&) = delete;
  mjVFS vfs;
};

int RequireId(const mjModel* model, mjtObj type, const char* name) {
  const int id = mj_name2id(model, type, name);
  if (id < 0) {
    throw std::runtime_error(std::string("robot model has no ") + mju_type2Str(type) + " named '" +
                             name + "'");
  }
  return id;
}

}  // namespace

void ValidateRobotModel(const std::string& robot_model_path, bool with_imu) {
  InstallMujocoHandlers();
  common::RequireRegularFile(robot_model_path, "robot model");
  char error[1024] = "";
  std::string reason;
  std::unique_ptr<mjModel, decltype(&mj_deleteModel)> model(nullptr, mj_deleteModel);
  try {
    model.reset(mj_loadXML(robot_model_path.c_str(), nullptr, error, sizeof(error)));
    reason = error;
  } catch (const std::runtime_error& e) {
    reason = e.what();
  }
  if (!model) {
    throw common::InputError(robot_model_path, "",
                             "is not a MuJoCo model that loads: " + common::Excerpt(reason, 300));
  }
  std::vector<std::string> missing;
  auto require = [&](mjtObj type, const std::string& name) {
    if (mj_name2id(model.get(), type, name.c_str()) < 0) {
      missing.push_back(std::string(mju_type2Str(type)) + " '" + name + "'");
    }
  };
  require(mjOBJ_BODY, "base");
  require(mjOBJ_JOINT, "root");
  require(mjOBJ_SITE, "lidar");
  for (int w = 0; w < 4; ++w) {
    require(mjOBJ_JOINT, kWheelJoints[w]);
    require(mjOBJ_ACTUATOR, kWheelActuators[w]);
  }
  if (with_imu) {
    require(mjOBJ_SENSOR, "imu_accel");
    require(mjOBJ_SENSOR, "imu_gyro");
  }
  if (!missing.empty()) {
    std::string list;
    for (const std::string& name : missing) list += (list.empty() ? "" : ", ") + name;
    throw common::InputError(robot_model_path, "",
                             "lacks what trav drives and senses: " + list + " (docs/robots.md)");
  }
  for (int w = 0; w < 4; ++w) {
    if (mj_name2id(model.get(), mjOBJ_ACTUATOR, kWheelActuators[w]) != w) {
      throw common::InputError(
          robot_model_path, "",
          std::string("actuator ") + kWheelActuators[w] + " must be number " + std::to_string(w));
    }
  }
}

std::string MujocoVersion() {
  const int version = mj_version();
  return std::to_string(version / 100) + "." + std::to_string(version / 10 % 10) + "." +
         std::to_string(version % 10);
}

void InstallMujocoHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = ThrowMujocoError;
    mju_user_warning = LogMujocoWarning;
  });
}

void Simulation::ModelDeleter::operator()(mjModel* model) const { mj_deleteModel(model); }
void Simulation::DataDeleter::operator()(mjData* data) const { mj_deleteData(data); }

Simulation::Simulation(const TerrainWorld& terrain, const common::Pose2& start_W,
                       const WorldOptions& options, const std::vector<MovingObstacle>& movers) {
  ValidateRobotModel(options.robot_model_path);
  ValidateMovingObstacles(movers);
  // load the generated world from a virtual file; the robot file is included from disk
  const std::string xml = BuildWorldXml(terrain, options, movers);
  // on the heap (about 2 MB), and freed however the load ends (MuJoCo errors throw through
  // mj_loadXML)
  const auto vfs = std::make_unique<ScopedVfs>();
  constexpr const char* kWorldFile = "trav_world.xml";
  if (mj_makeEmptyFileVFS(&vfs->vfs, kWorldFile, static_cast<int>(xml.size())) != 0) {
    throw std::runtime_error("MuJoCo VFS: cannot allocate the world file");
  }
  std::memcpy(vfs->vfs.filedata[mj_findFileVFS(&vfs->vfs, kWorldFile)], xml.data(), xml.size());
  char error[1024] = "";
  model_.reset(mj_loadXML(kWorldFile, &vfs->vfs, error, sizeof(error)));
  if (!model_) throw std::runtime_error(std::string("cannot build the MuJoCo world: ") + error);

  // height samples from memory (the asset declares only the size)
  const HeightFieldLayout layout = ComputeHeightFieldLayout(terrain);
  const int hfield = RequireId(model_.get(), mjOBJ_HFIELD, "terrain");
  FillHeightField(terrain.height_m, layout, model_->hfield_data + model_->hfield_adr[hfield]);
  const Eigen::MatrixXf visual_height_m = ResampleGround(terrain, options.visual_max_samples);
  const int visual_hfield = RequireId(model_.get(), mjOBJ_HFIELD, "terrain_visual");
  FillHeightField(visual_height_m, layout, model_->hfield_data + model_->hfield_adr[visual_hfield]);

  data_.reset(mj_makeData(model_.get()));
  if (!data_) throw std::runtime_error("MuJoCo: cannot allocate mjData");

  base_body_id_ = RequireId(model_.get(), mjOBJ_BODY, "base");
  lidar_site_id_ = RequireId(model_.get(), mjOBJ_SITE, "lidar");
  const int accelerometer = mj_name2id(model_.get(), mjOBJ_SENSOR, "imu_accel");
  const int gyro = mj_name2id(model_.get(), mjOBJ_SENSOR, "imu_gyro");
  if (accelerometer >= 0 && gyro >= 0 &&
      model_->sensor_type[accelerometer] == mjSENS_ACCELEROMETER &&
      model_->sensor_type[gyro] == mjSENS_GYRO) {
    imu_accel_address_ = model_->sensor_adr[accelerometer];
    imu_gyro_address_ = model_->sensor_adr[gyro];
  }
  const int root = RequireId(model_.get(), mjOBJ_JOINT, "root");
  root_qpos_address_ = model_->jnt_qposadr[root];
  root_qvel_address_ = model_->jnt_dofadr[root];
  for (int w = 0; w < 4; ++w) {
    wheel_qvel_address_[w] =
        model_->jnt_dofadr[RequireId(model_.get(), mjOBJ_JOINT, kWheelJoints[w])];
    if (RequireId(model_.get(), mjOBJ_ACTUATOR, kWheelActuators[w]) != w) {
      throw std::runtime_error(std::string("robot model: actuator ") + kWheelActuators[w] +
                               " must be number " + std::to_string(w));
    }
  }

  // the bare ground: the movers' tracks and the obstacles' heights at a contact
  ground_.config = terrain.config;
  ground_.geometry = terrain.geometry;
  ground_.height_m = terrain.height_m;
  // movers: tracks over the bare ground, at their pose at t = 0
  for (const MovingObstacle& mover : movers) {
    const int body = RequireId(model_.get(), mjOBJ_BODY, ("mover_" + mover.name).c_str());
    mover_mocap_ids_.push_back(model_->body_mocapid[body]);
    mover_body_ids_.push_back(body);
    mover_tracks_.emplace_back(mover);
  }
  mover_velocities_W_.assign(movers.size(), Eigen::Vector2d::Zero());
  SetMoverPoses(0.0);
  ClassifyGeoms(terrain);
  PlaceRobot(terrain, start_W);
  footprint_ = MeasureFootprint();
}

common::Footprint Simulation::MeasureFootprint() const {
  const mjModel* m = model_.get();
  const Eigen::Isometry3d X_WB =
      FramePose(data_->xpos + 3 * base_body_id_, data_->xmat + 9 * base_body_id_);
  const int robot_root = m->body_rootid[base_body_id_];
  Eigen::Vector2d extent_B = Eigen::Vector2d::Zero();
  for (int g = 0; g < m->ngeom; ++g) {
    const int body = m->geom_bodyid[g];
    if (m->body_rootid[body] != robot_root ||
        (m->geom_contype[g] == 0 && m->geom_conaffinity[g] == 0))
      continue;
    const mjtNum* size = m->geom_size + 3 * g;
    // half extents of a box round the geom in its own frame; the bounding sphere for other types
    Eigen::Vector3d half;
    switch (m->geom_type[g]) {
      case mjGEOM_BOX:
      case mjGEOM_ELLIPSOID:
        half = Eigen::Vector3d(size[0], size[1], size[2]);
        break;
      case mjGEOM_CYLINDER:
        half = Eigen::Vector3d(size[0], size[0], size[1]);
        break;
      case mjGEOM_CAPSULE:
        half = Eigen::Vector3d(size[0], size[0], size[1] + size[0]);
        break;
      default:
        half = Eigen::Vector3d::Constant(m->geom_rbound[g]);
    }
    const Eigen::Isometry3d X_BG =
        X_WB.inverse() * FramePose(data_->geom_xpos + 3 * g, data_->geom_xmat + 9 * g);
    const Eigen::Vector3d reach = X_BG.linear().cwiseAbs() * half;
    extent_B = extent_B.cwiseMax(X_BG.translation().head<2>().cwiseAbs() + reach.head<2>());
  }
  return {extent_B.x(), extent_B.y()};
}

Simulation::~Simulation() = default;

void Simulation::ClassifyGeoms(const TerrainWorld& terrain) {
  std::unordered_map<std::string_view, int> obstacle_index;
  for (std::size_t k = 0; k < terrain.obstacles.size(); ++k) {
    obstacle_index.emplace(terrain.obstacles[k].name, static_cast<int>(k));
  }
  std::unordered_map<std::string_view, int> mover_index;
  for (std::size_t k = 0; k < mover_tracks_.size(); ++k) {
    mover_index.emplace(mover_tracks_[k].mover().name, static_cast<int>(k));
  }
  constexpr std::string_view kMoverPrefix = "mover_";
  geom_info_.assign(static_cast<std::size_t>(model_->ngeom), GeomInfo{});
  for (int g = 0; g < model_->ngeom; ++g) {
    GeomInfo& info = geom_info_[static_cast<std::size_t>(g)];
    const char* name = mj_id2name(model_.get(), mjOBJ_GEOM, g);
    if (name != nullptr) info.name = name;
    const int body = model_->geom_bodyid[g];
    if (model_->body_rootid[body] == base_body_id_) {
      info.kind = GeomKind::kBody;
      for (int w = 0; w < 4; ++w) {
        if (info.name == kWheelJoints[w]) {
          info.kind = GeomKind::kWheel;
          info.index = w;
        }
      }
    } else if (info.name == "ground") {
      info.kind = GeomKind::kTerrain;
    } else if (model_->body_mocapid[body] >= 0 &&
               info.name.substr(0, kMoverPrefix.size()) == kMoverPrefix) {
      const auto it = mover_index.find(info.name.substr(kMoverPrefix.size()));
      if (it != mover_index.end()) {
        info.kind = GeomKind::kMover;
        info.index = it->second;
        info.name.remove_prefix(kMoverPrefix.size());
        info.height_m =
            2.0 * mover_tracks_[static_cast<std::size_t>(it->second)].mover().half_height_m;
      }
    } else if (const auto it = obstacle_index.find(info.name); it != obstacle_index.end()) {
      const Obstacle& obstacle = terrain.obstacles[static_cast<std::size_t>(it->second)];
      info.kind = GeomKind::kObstacle;
      info.index = it->second;
      info.height_m = TopOf(obstacle) - terrain.GroundHeight(obstacle.X_WO.translation().head<2>());
    }
  }
}

void Simulation::PlaceRobot(const TerrainWorld& terrain, const common::Pose2& start_W) {
  // fit the ground plane under the four wheels: height, pitch and roll
  const Eigen::Rotation2Dd yaw(start_W.yaw);
  double heights[4];
  const double signs_x[4] = {1, -1, 1, -1};
  const double signs_y[4] = {1, 1, -1, -1};
  for (int w = 0; w < 4; ++w) {
    const Eigen::Vector2d p_W =
        start_W.position + yaw * Eigen::Vector2d(signs_x[w] * kWheelX_m, signs_y[w] * kWheelY_m);
    heights[w] = terrain.GroundHeight(p_W);
  }
  const double front = 0.5 * (heights[0] + heights[2]);
  const double rear = 0.5 * (heights[1] + heights[3]);
  const double left = 0.5 * (heights[0] + heights[1]);
  const double right = 0.5 * (heights[2] + heights[3]);
  const double pitch = -std::atan2(front - rear, 2.0 * kWheelX_m);
  const double roll = std::atan2(left - right, 2.0 * kWheelY_m);
  const double highest = std::max({heights[0], heights[1], heights[2], heights[3]});

  const Eigen::Quaterniond q(Eigen::AngleAxisd(start_W.yaw, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
  mjtNum* qpos = data_->qpos + root_qpos_address_;
  qpos[0] = start_W.position.x();
  qpos[1] = start_W.position.y();
  qpos[2] = highest + kWheelRadius_m + kDropHeight_m;
  qpos[3] = q.w();
  qpos[4] = q.x();
  qpos[5] = q.y();
  qpos[6] = q.z();
  mj_forward(model_.get(), data_.get());
}

void Simulation::SetMoverPoses(double t_s) {
  for (int i = 0; i < num_movers(); ++i) {
    MoverTrack& track = mover_tracks_[static_cast<std::size_t>(i)];
    const MoverPlanarState state = track.PlanarStateAt(t_s);
    SetMoverPose(i, sim::MoverPose(track.mover(), state, ground_), state.v_W);
  }
}

void Simulation::CheckMoverIndex(int index) const {
  if (index < 0 || index >= num_movers()) {
    throw std::out_of_range("Simulation: no mover " + std::to_string(index) + " (there are " +
                            std::to_string(num_movers()) + ")");
  }
}

void Simulation::SetMoverPose(int index, const Eigen::Isometry3d& X_WO,
                              const Eigen::Vector2d& v_W) {
  CheckMoverIndex(index);
  const int mocap = mover_mocap_ids_[static_cast<std::size_t>(index)];
  const Eigen::Quaterniond q(X_WO.linear());
  mjtNum* pos = data_->mocap_pos + 3 * mocap;
  mjtNum* quat = data_->mocap_quat + 4 * mocap;
  for (int k = 0; k < 3; ++k) pos[k] = X_WO.translation()[k];
  quat[0] = q.w();
  quat[1] = q.x();
  quat[2] = q.y();
  quat[3] = q.z();
  mover_velocities_W_[static_cast<std::size_t>(index)] = v_W;
}

Eigen::Isometry3d Simulation::MoverPose(int index) const {
  CheckMoverIndex(index);
  const int mocap = mover_mocap_ids_[static_cast<std::size_t>(index)];
  const mjtNum* pos = data_->mocap_pos + 3 * mocap;
  const mjtNum* quat = data_->mocap_quat + 4 * mocap;
  Eigen::Isometry3d X_WO = Eigen::Isometry3d::Identity();
  X_WO.linear() = Eigen::Quaterniond(quat[0], quat[1], quat[2], quat[3]).toRotationMatrix();
  X_WO.translation() = Eigen::Vector3d(pos[0], pos[1], pos[2]);
  return X_WO;
}

Eigen::Vector2d Simulation::MoverVelocity(int index) const {
  CheckMoverIndex(index);
  return mover_velocities_W_[static_cast<std::size_t>(index)];
}

void Simulation::RobotContacts(std::vector<RobotContact>* contacts) const {
  contacts->clear();
  const Eigen::Vector2d v_robot_W(data_->qvel[root_qvel_address_],
                                  data_->qvel[root_qvel_address_ + 1]);
  for (int i = 0; i < data_->ncon; ++i) {
    const mjContact& contact = data_->contact[i];
    if (contact.exclude == 1) continue;  // within the margin, not touching
    const GeomInfo& first = geom_info_[static_cast<std::size_t>(contact.geom1)];
    const GeomInfo& second = geom_info_[static_cast<std::size_t>(contact.geom2)];
    const auto on_robot = [](const GeomInfo& info) {
      return info.kind == GeomKind::kWheel || info.kind == GeomKind::kBody;
    };
    if (on_robot(first) == on_robot(second)) continue;
    const bool robot_first = on_robot(first);
    const GeomInfo& robot = robot_first ? first : second;
    const GeomInfo& other = robot_first ? second : first;
    RobotContact report;
    switch (other.kind) {
      case GeomKind::kTerrain:
        report.target = ContactTarget::kTerrain;
        break;
      case GeomKind::kObstacle:
        report.target = ContactTarget::kObstacle;
        break;
      case GeomKind::kMover:
        report.target = ContactTarget::kMover;
        report.relative_speed_m_s =
            (v_robot_W - mover_velocities_W_[static_cast<std::size_t>(other.index)]).norm();
        break;
      default:
        continue;
    }
    report.part = robot.kind == GeomKind::kWheel ? RobotPart::kWheel : RobotPart::kBody;
    report.wheel = robot.kind == GeomKind::kWheel ? robot.index : -1;
    report.target_index = other.index;
    report.target_name = other.name;
    report.p_W = Eigen::Vector3d(contact.pos[0], contact.pos[1], contact.pos[2]);
    // MuJoCo's normal points from geom1 to geom2
    const Eigen::Vector3d normal(contact.frame[0], contact.frame[1], contact.frame[2]);
    report.normal_W = robot_first ? Eigen::Vector3d(-normal) : normal;
    report.target_height_m = other.kind == GeomKind::kObstacle
                                 ? ObstacleHeightAt(robot_first ? contact.geom2 : contact.geom1,
                                                    report.p_W, report.normal_W, other.height_m)
                                 : other.height_m;
    report.penetration_m = std::max(0.0, -contact.dist);
    if (contact.efc_address >= 0) {
      mjtNum force[6];
      mj_contactForce(model_.get(), data_.get(), i, force);
      report.normal_force_N = std::max(0.0, force[0]);
    }
    contacts->push_back(report);
  }
}

double Simulation::ObstacleHeightAt(int geom, const Eigen::Vector3d& p_W,
                                    const Eigen::Vector3d& normal_W, double fallback_m) const {
  // 1 cm inside the face along the normal's horizontal part (the normal points to the robot)
  constexpr double kInside_m = 0.01;
  Eigen::Vector2d inward = -normal_W.head<2>();
  const double horizontal = inward.norm();
  Eigen::Vector2d p = p_W.head<2>();
  if (horizontal > 1e-9) p += kInside_m / horizontal * inward;
  // straight down from above the geom's bounding sphere onto the geom alone
  const mjtNum* centre = data_->geom_xpos + 3 * geom;
  const mjtNum start[3] = {p.x(), p.y(), centre[2] + model_->geom_rbound[geom] + 1.0};
  const mjtNum down[3] = {0.0, 0.0, -1.0};
  const mjtNum distance =
      mju_rayGeom(centre, data_->geom_xmat + 9 * geom, model_->geom_size + 3 * geom, start, down,
                  model_->geom_type[geom]);
  if (distance < 0.0) return fallback_m;
  return start[2] - distance - ground_.GroundHeight(p);
}

void Simulation::SetWheelSpeedCommands(const common::WheelSpeeds& speeds_rad_s) {
  for (int w = 0; w < 4; ++w) data_->ctrl[w] = speeds_rad_s[w];
}

StepStatus Simulation::Step() {
  mj_step(model_.get(), data_.get());
  CollectWarnings();
  const bool bad_state = data_->warning[mjWARN_BADQPOS].number > 0 ||
                         data_->warning[mjWARN_BADQVEL].number > 0 ||
                         data_->warning[mjWARN_BADQACC].number > 0 ||
                         !std::isfinite(data_->qpos[root_qpos_address_ + 2]);
  return bad_state ? StepStatus::kDiverged : StepStatus::kOk;
}

void Simulation::CollectWarnings() {
  for (int kind = 0; kind < mjNWARNING; ++kind) {
    const int number = data_->warning[kind].number;
    if (number == last_warning_numbers_[kind]) continue;
    if (last_warning_numbers_[kind] == 0) {
      warning_messages_.push_back(std::string(WarningName(kind)) +
                                  " at t = " + std::to_string(data_->time) + " s (info " +
                                  std::to_string(data_->warning[kind].lastinfo) + ")");
    }
    warning_count_ += number - last_warning_numbers_[kind];
    last_warning_numbers_[kind] = number;
  }
}

common::RobotState Simulation::State() const {
  common::RobotState state;
  state.time_s = data_->time;
  state.X_WB = FramePose(data_->xpos + 3 * base_body_id_, data_->xmat + 9 * base_body_id_);
  // free joint velocity: linear in W, angular in B
  const mjtNum* qvel = data_->qvel + root_qvel_address_;
  state.v_WB_B = state.X_WB.linear().transpose() * Eigen::Vector3d(qvel[0], qvel[1], qvel[2]);
  state.w_WB_B = Eigen::Vector3d(qvel[3], qvel[4], qvel[5]);
  for (int w = 0; w < 4; ++w) state.wheel_speeds[w] = data_->qvel[wheel_qvel_address_[w]];
  return state;
}

Eigen::Isometry3d Simulation::LidarPose() const {
  return FramePose(data_->site_xpos + 3 * lidar_site_id_, data_->site_xmat + 9 * lidar_site_id_);
}

std::optional<ImuMeasurement> Simulation::ImuTruth() const {
  if (imu_accel_address_ < 0) return std::nullopt;
  const mjtNum* accel = data_->sensordata + imu_accel_address_;
  const mjtNum* gyro = data_->sensordata + imu_gyro_address_;
  ImuMeasurement truth;
  truth.accel_I = Eigen::Vector3d(accel[0], accel[1], accel[2]);
  truth.gyro_I = Eigen::Vector3d(gyro[0], gyro[1], gyro[2]);
  return truth;
}

double Simulation::time() const { return data_->time; }

double Simulation::timestep() const { return model_->opt.timestep; }

}  // namespace trav::sim
