#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/pose.h"
#include "sim/terrain.h"
#include "sim/world_builder.h"

// MuJoCo's types, forward-declared so that its headers stay inside sim/ and renders/ sources.
struct mjModel_;
struct mjData_;
typedef struct mjModel_ mjModel;
typedef struct mjData_ mjData;

namespace trav::sim {

/// Outcome of one physics step.
enum class StepStatus {
  kOk,        ///< stepped normally
  kDiverged,  ///< MuJoCo reported a bad state (NaN or huge qpos, qvel or qacc) or the state is not
              ///< finite
};

/// A MuJoCo world built from a generated terrain with the Scout Mini on it, stepped at a fixed
/// timestep. Owns mjModel and mjData (RAII); stepping allocates nothing. MuJoCo warnings are
/// counted and kept as messages; MuJoCo errors become exceptions.
class Simulation {
 public:
  /// Builds the world of `terrain` and places the robot with its base B at `start_W` (x, y, yaw),
  /// aligned with the ground under its wheels and dropped from 1 cm above it.
  /// @throws std::runtime_error if the robot model cannot be loaded or the world does not compile.
  Simulation(const TerrainWorld& terrain, const common::Pose2& start_W,
             const WorldOptions& options);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Sets the wheel speed commands [rad/s] (front-left, rear-left, front-right, rear-right); the
  /// velocity actuators clamp them to their control range.
  void SetWheelSpeedCommands(const common::WheelSpeeds& speeds_rad_s);

  /// Advances the world by one timestep.
  StepStatus Step();

  /// Ground-truth state of the robot base.
  common::RobotState State() const;

  /// Pose of the LiDAR site L in W.
  Eigen::Isometry3d LidarPose() const;

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
  void PlaceRobot(const TerrainWorld& terrain, const common::Pose2& start_W);
  void CollectWarnings();

  std::unique_ptr<mjModel, ModelDeleter> model_;
  std::unique_ptr<mjData, DataDeleter> data_;
  int base_body_id_{-1};
  int lidar_site_id_{-1};
  int root_qpos_address_{0};
  int root_qvel_address_{0};
  std::array<int, 4> wheel_qvel_address_{};
  std::array<int, 8> last_warning_numbers_{};
  int warning_count_{0};
  std::vector<std::string> warning_messages_;
};

/// Installs MuJoCo's error and warning handlers (once per process): errors throw
/// std::runtime_error, warnings go to the trav logger at debug level. MuJoCo's C API offers only
/// process-wide handlers; without them it prints and exits.
void InstallMujocoHandlers();

}  // namespace trav::sim
