#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "common/footprint.h"
#include "common/pose.h"
#include "sim/moving_obstacles.h"
#include "sim/terrain.h"
#include "sim/world_builder.h"

// MuJoCo's types, forward-declared so that its headers stay inside sim/ and renders/ sources.
struct mjModel_;
struct mjData_;
typedef struct mjModel_ mjModel;
typedef struct mjData_ mjData;

namespace trav::sim {

/// What an IMU measures in its own frame I: the specific force (acceleration minus gravity, so
/// +9.81 m/s^2 up at rest) [m/s^2] and the angular velocity [rad/s].
struct ImuMeasurement {
  Eigen::Vector3d accel_I{Eigen::Vector3d::Zero()};
  Eigen::Vector3d gyro_I{Eigen::Vector3d::Zero()};
};

/// Outcome of one physics step.
enum class StepStatus {
  kOk,        ///< stepped normally
  kDiverged,  ///< MuJoCo reported a bad state (NaN or huge qpos, qvel or qacc) or the state is not
              ///< finite
};

/// The part of the robot in a contact.
enum class RobotPart {
  kWheel,  ///< one of the four wheels
  kBody,   ///< the chassis
};

/// What the robot touches.
enum class ContactTarget {
  kTerrain,   ///< the ground height field
  kObstacle,  ///< a static obstacle of TerrainWorld::obstacles (solid or ceiling)
  kMover,     ///< a moving obstacle
};

/// Static obstacles whose top is at most this high above the ground where the chassis touches
/// them [m] pass under it: the Scout Mini's ground clearance.
constexpr double kDriveOverHeight_m = 0.115;

/// Static obstacles whose top is at most this high above the ground where a wheel touches them
/// [m] are climbed, not hit: at 1 m/s the Scout Mini climbs a 0.16 m step and not a 0.17 m one
/// (tests/sim/simulation_test.cc, ClimbsSixteenCentimetresAtOneMetrePerSecondButNotSeventeen).
/// The ruin's rubble (up to 0.15 m) is such an obstacle.
constexpr double kClimbableStep_m = 0.16;

/// One contact between the robot and the world, from MuJoCo's contact list.
struct RobotContact {
  RobotPart part{RobotPart::kBody};
  int wheel{-1};  ///< common::Wheel index of a wheel contact, -1 for the body
  ContactTarget target{ContactTarget::kTerrain};
  /// Index into TerrainWorld::obstacles (kObstacle) or into the movers (kMover); -1 for the
  /// terrain.
  int target_index{-1};
  /// Obstacle or mover name, "ground" for the terrain; valid while the Simulation lives.
  std::string_view target_name;
  /// Height of the target above the ground [m]: a static obstacle's top over the contact point
  /// (its surface on the vertical 1 cm inside the touched face: a tilted slab met at its low edge
  /// is that edge's height, not its centre's), a mover's full height; 0 for the terrain.
  double target_height_m{0.0};
  Eigen::Vector3d p_W{Eigen::Vector3d::Zero()};        ///< contact point, midway between surfaces
  Eigen::Vector3d normal_W{Eigen::Vector3d::UnitZ()};  ///< unit normal from the target to the robot
  double penetration_m{0.0};                           ///< depth of the overlap [m], >= 0
  double normal_force_N{0.0};                          ///< normal force of the contact [N], >= 0
  /// Mover contacts: planar speed of the robot base relative to the mover [m/s]; 0 otherwise.
  double relative_speed_m_s{0.0};
};

/// The collision rule of the outcome classification: any part of the robot (chassis or wheel)
/// touching a mover; the chassis touching a static obstacle taller than `drive_over_height_m`
/// where it touches it; a wheel touching one taller there than `climbable_step_m` (a wheel against
/// a tree trunk or a wall is a collision: the wheels stick out 3 cm beyond the chassis, so driving
/// into a wall touches it with the wheels first; a wheel meeting rubble it climbs is not). A static
/// obstacle touched from above (contact normal within about 45 deg of up: the robot on top of it,
/// or going over the edge of a ledge) is not a collision either, as the robot got there without
/// hitting a face. Contacts with the terrain are never collisions; the chassis on the terrain (a
/// belly on a ridge) is reported as a body contact with kTerrain.
inline bool IsCollision(const RobotContact& contact,
                        double drive_over_height_m = kDriveOverHeight_m,
                        double climbable_step_m = kClimbableStep_m) {
  constexpr double kFromAbove = 0.7;  // cos 45 deg
  switch (contact.target) {
    case ContactTarget::kTerrain:
      return false;
    case ContactTarget::kObstacle:
      return contact.target_height_m >
                 (contact.part == RobotPart::kWheel ? climbable_step_m : drive_over_height_m) &&
             contact.normal_W.z() < kFromAbove;
    case ContactTarget::kMover:
      return true;
  }
  return false;
}

/// A MuJoCo world built from a generated terrain with the Scout Mini on it, stepped at a fixed
/// timestep. Owns mjModel and mjData (RAII); stepping allocates nothing. MuJoCo warnings are
/// counted and kept as messages; MuJoCo errors become exceptions.
class Simulation {
 public:
  /// Builds the world of `terrain` with `movers` (mocap bodies at their pose at t = 0) and places
  /// the robot with its base B at `start_W` (x, y, yaw), aligned with the ground under its wheels
  /// and dropped from 1 cm above it.
  /// @throws common::InputError for invalid movers (key paths "[i].<field>",
  /// ValidateMovingObstacles).
  /// @throws std::runtime_error if the robot model cannot be loaded or the world does not compile.
  Simulation(const TerrainWorld& terrain, const common::Pose2& start_W, const WorldOptions& options,
             const std::vector<MovingObstacle>& movers = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Sets the wheel speed commands [rad/s] (front-left, rear-left, front-right, rear-right); the
  /// velocity actuators clamp them to their control range.
  void SetWheelSpeedCommands(const common::WheelSpeeds& speeds_rad_s);

  /// Advances the world by one timestep. Movers stay where they were last put.
  StepStatus Step();

  /// Number of moving obstacles; index i is movers[i] of the constructor (and moving object i of
  /// RaySceneOf(world, movers)).
  int num_movers() const { return static_cast<int>(mover_tracks_.size()); }

  /// Moves every mover to its pose at time t_s [s] (MoverTrack) and records its velocity; call it
  /// before each Step with the simulation time. Allocates nothing once a random walker's legs up to
  /// t_s are drawn.
  void SetMoverPoses(double t_s);

  /// Puts mover `index` at X_WO (its frame O in W) with planar velocity v_W [m/s] (used for the
  /// relative speed of contacts). @throws std::out_of_range for a bad index.
  void SetMoverPose(int index, const Eigen::Isometry3d& X_WO,
                    const Eigen::Vector2d& v_W = Eigen::Vector2d::Zero());

  /// Pose of mover `index` in W as last set (what the next Step uses), and its planar velocity
  /// [m/s]. @throws std::out_of_range for a bad index.
  Eigen::Isometry3d MoverPose(int index) const;
  Eigen::Vector2d MoverVelocity(int index) const;

  /// The MuJoCo body of mover `index` (its mocap body "mover_<name>"), for renderers.
  /// @throws std::out_of_range for a bad index.
  int MoverBodyId(int index) const { return mover_body_ids_.at(static_cast<std::size_t>(index)); }

  /// The robot's contacts found by the last Step (or by construction): clears `contacts` and
  /// appends one entry per MuJoCo contact between a robot geom and the world (no allocation once
  /// the vector has grown to the largest count). Use IsCollision to classify them.
  void RobotContacts(std::vector<RobotContact>* contacts) const;

  /// Ground-truth state of the robot base.
  common::RobotState State() const;

  /// The rectangle round the robot's collision geometry (chassis and wheels) in its base frame B,
  /// centred on B's origin, as the robot file builds it at the start pose.
  const common::Footprint& RobotFootprint() const { return footprint_; }

  /// Pose of the LiDAR site L in W.
  Eigen::Isometry3d LidarPose() const;

  /// The true readings of the robot's IMU (the model's accelerometer `imu_accel` and gyro
  /// `imu_gyro` at its `imu` site), as MuJoCo computed them in the last Step for the state at the
  /// step's start; nothing when the model has no such sensors.
  std::optional<ImuMeasurement> ImuTruth() const;

  /// Simulation time [s].
  double time() const;

  /// Physics timestep [s].
  double timestep() const;

  /// Number of MuJoCo warnings raised so far, and their messages (one per kind, first occurrence).
  int warning_count() const { return warning_count_; }
  const std::vector<std::string>& warnings() const { return warning_messages_; }

  /// The MuJoCo model and data, for the renderer. Only visual settings of the model may be changed.
  const mjModel* model() const { return model_.get(); }
  mjModel* mutable_model() { return model_.get(); }
  const mjData* data() const { return data_.get(); }

 private:
  struct ModelDeleter {
    void operator()(mjModel* model) const;
  };
  struct DataDeleter {
    void operator()(mjData* data) const;
  };
  // What a MuJoCo geom is in contact reports.
  enum class GeomKind { kOther, kWheel, kBody, kTerrain, kObstacle, kMover };
  struct GeomInfo {
    GeomKind kind{GeomKind::kOther};
    int index{-1};  // wheel, obstacle or mover index
    double height_m{0.0};
    std::string_view name;  // into the model's names (a mover's without the "mover_" prefix)
  };
  void ClassifyGeoms(const TerrainWorld& terrain);
  // RobotContact::target_height_m of obstacle geom `geom` touched at p_W with normal_W (from the
  // obstacle to the robot); `fallback_m` (its top above the ground under its centre) where the
  // vertical misses the geom.
  double ObstacleHeightAt(int geom, const Eigen::Vector3d& p_W, const Eigen::Vector3d& normal_W,
                          double fallback_m) const;
  void PlaceRobot(const TerrainWorld& terrain, const common::Pose2& start_W);
  common::Footprint MeasureFootprint() const;
  void CheckMoverIndex(int index) const;
  void CollectWarnings();

  std::unique_ptr<mjModel, ModelDeleter> model_;
  std::unique_ptr<mjData, DataDeleter> data_;
  int base_body_id_{-1};
  int lidar_site_id_{-1};
  int imu_accel_address_{-1};  // in sensordata; -1: no accelerometer imu_accel
  int imu_gyro_address_{-1};
  int root_qpos_address_{0};
  int root_qvel_address_{0};
  std::array<int, 4> wheel_qvel_address_{};
  common::Footprint footprint_;
  std::vector<GeomInfo> geom_info_;  // per MuJoCo geom
  std::vector<MoverTrack> mover_tracks_;
  std::vector<int> mover_mocap_ids_;
  std::vector<int> mover_body_ids_;
  std::vector<Eigen::Vector2d> mover_velocities_W_;
  // the terrain's heights without obstacles (only with movers), to stand the movers on
  TerrainWorld ground_;
  std::array<int, 8> last_warning_numbers_{};
  int warning_count_{0};
  std::vector<std::string> warning_messages_;
};

/// Installs MuJoCo's error and warning handlers (once per process): errors throw
/// std::runtime_error, warnings go to the trav logger at debug level. MuJoCo's C API offers only
/// process-wide handlers; without them it prints and exits.
void InstallMujocoHandlers();

/// Checks that `robot_model_path` is a MuJoCo model that loads on its own and has what trav drives
/// and senses: the free joint `root` of the body `base`, the site `lidar`, the wheel joints
/// front_left_wheel, rear_left_wheel, front_right_wheel, rear_right_wheel and their velocity
/// actuators front_left_motor, rear_left_motor, front_right_motor, rear_right_motor, in this order.
/// @throws common::InputError naming the file and what is wrong.
/// With `with_imu`, the accelerometer `imu_accel` and gyro `imu_gyro` of the IMU are required too.
void ValidateRobotModel(const std::string& robot_model_path, bool with_imu = false);

/// The robot file as a URDF for ROS tools (RViz, robot_state_publisher): one link per body with its
/// mass and inertia as MuJoCo computes them, its geoms as collision (those that collide) and visual
/// geometry, a fixed link per site (`lidar`, `imu`); the free joint `root` is left out (the base is
/// the root link, `base_link` after REP-105), hinges become continuous or revolute joints, slides
/// prismatic ones. URDF has no ellipsoid: an ellipsoid with two equal semi-axes (trav's wheels) is
/// written as the cylinder of those axes and the third's length, others as a box round them.
/// @throws common::InputError naming the file if it is not a MuJoCo model that loads, or holds a
/// body with more than one joint, a ball joint or a mesh (URDF cannot say them).
std::string RobotUrdf(const std::string& robot_model_path);

/// The version of the MuJoCo library trav runs with ("2.2.2").
std::string MujocoVersion();

}  // namespace trav::sim
