#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "common/serial_worker.h"
#include "sim/lidar/lidar_emulator.h"
#include "sim/lidar/ray_scene.h"

namespace trav::scenarios {

/// One physics step of scanning: the rays with time stamps in [t_begin_s, t_end_s), cast from the
/// sensor pose X_WL with the ray scene's moving objects at `movers_X_WI` (one pose per moving
/// object, in the scene's order; empty when it has none).
struct ScanStep {
  double t_begin_s{0.0};
  double t_end_s{0.0};
  Eigen::Isometry3d X_WL{Eigen::Isometry3d::Identity()};
  std::vector<Eigen::Isometry3d> movers_X_WI;
};

/// The LiDAR of a closed loop: its ray scene and emulator, scanned one physics step at a time, on
/// the loop's thread or on a worker of its own. With the worker, a step's rays are cast while the
/// loop goes on (the control, the physics, the next steps), and the loop waits only where a frame
/// completes, for the steps queued before it. The frames are the same either way, bit for bit:
/// the worker scans the same steps, with the same poses, in the same order, and nothing else
/// touches the emulator (its seeded noise) or the scene; which steps complete a frame follows from
/// their times alone (LidarEmulator::RaysBefore), so the loop knows it without asking the worker.
class LidarPipeline {
 public:
  /// Takes the scene and the emulator; `worker_thread` scans on a thread of its own.
  LidarPipeline(std::unique_ptr<lidar::RayScene> scene,
                std::unique_ptr<lidar::LidarEmulator> emulator, bool worker_thread);
  /// Stops the worker; steps not yet scanned are dropped.
  ~LidarPipeline() = default;
  LidarPipeline(const LidarPipeline&) = delete;
  LidarPipeline& operator=(const LidarPipeline&) = delete;

  /// Queues a step; steps must come in order and not overlap. @returns true when the step
  /// completes a frame, which TakeFrame then hands out (before the next Submit).
  bool Submit(ScanStep step);

  /// Waits for the queued steps and moves the complete frame into `frame`. Precondition (checked):
  /// the last Submit completed a frame. Rethrows what a scan threw.
  void TakeFrame(lidar::LidarFrame* frame);

  /// Waits for the queued steps and appends the wall time [ms] of each step scanned since the last
  /// call to `step_ms`. Rethrows what a scan threw.
  void TakeStepTimes(std::vector<double>* step_ms);

  /// True when the steps are scanned on a worker thread.
  bool threaded() const { return worker_ != nullptr; }

 private:
  // Scans `step` into the emulator's frame; returns its wall time [ms].
  double Scan(const ScanStep& step);

  std::unique_ptr<lidar::RayScene> scene_;
  std::unique_ptr<lidar::LidarEmulator> emulator_;
  std::int64_t rays_submitted_{0};  // rays fired before the end of the last step submitted
  bool frame_due_{false};           // the last step submitted completed a frame
  std::vector<double> step_ms_;     // wall times of the steps scanned and not yet handed out
  // the worker (null: steps are scanned inline), the only user of the scene and the emulator
  // while steps are queued
  std::unique_ptr<common::SerialWorker<ScanStep, double>> worker_;
};

}  // namespace trav::scenarios
