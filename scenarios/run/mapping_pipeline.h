#pragma once

#include <deque>
#include <memory>
#include <optional>

#include <Eigen/Geometry>

#include "common/grid.h"
#include "common/point_cloud.h"
#include "common/serial_worker.h"
#include "mapping/traversability_mapper.h"

namespace trav::scenarios {

/// A LiDAR frame for the mapper: its points (movers removed) and the base pose, both in the
/// odometry frame O, the time it was scanned, and the simulation time at which its map takes
/// effect (the scan time plus the modelled mapping latency).
struct MapInput {
  double ready_s{0.0};
  common::PointCloud cloud_O;
  Eigen::Isometry3d X_OB{Eigen::Isometry3d::Identity()};
  double scan_time_s{0.0};
};

/// One map update as it takes effect.
struct MapUpdate {
  mapping::MapUpdateResult result;
  double mapping_ms{0.0};  ///< wall time of the mapper's Update [ms]
};

/// Feeds a mapper its LiDAR frames in order and hands each frame's map out at the simulation time
/// its latency fixes. Without a worker thread a frame is mapped when it is due. With one, a frame
/// is mapped on the worker as soon as it arrives, while the loop goes on (the physics, the
/// control, the next frame's rays), and its map is copied for hand-out. What is handed out is the
/// same either way, bit for bit: the mapper sees the same frames in the same order and nothing
/// else, and a map takes effect at its ready time, never when the worker happens to finish (the
/// loop waits for a late worker). So a run does not depend on the machine's load.
class MappingPipeline {
 public:
  /// Takes the mapper; `worker_thread` maps on a thread of its own.
  MappingPipeline(std::unique_ptr<mapping::TraversabilityMapper> mapper, bool worker_thread);
  /// Stops the worker; frames not yet mapped are dropped.
  ~MappingPipeline() = default;
  MappingPipeline(const MappingPipeline&) = delete;
  MappingPipeline& operator=(const MappingPipeline&) = delete;

  /// Queues a frame; frames must come in order of their ready times.
  void Submit(MapInput input);

  /// The update of the oldest queued frame if it is due at simulation time `now_s` (its ready time
  /// is at most `now_s`), in the order submitted; nullopt when none is due. Its map is map() from
  /// then on. Rethrows what the mapper threw.
  std::optional<MapUpdate> NextDue(double now_s);

  /// The map of the latest update handed out by NextDue; null before the first.
  const common::GridLayers* map() const { return map_; }

  /// True when frames are mapped on a worker thread.
  bool threaded() const { return worker_ != nullptr; }

 private:
  // A frame's update and a copy of the map after it, as the worker hands them back.
  struct Done {
    MapUpdate update;
    common::GridLayers map;
  };

  MapUpdate Map(const MapInput& input);

  std::unique_ptr<mapping::TraversabilityMapper> mapper_;
  std::deque<double> queued_ready_s_;  // of every frame submitted and not yet handed out
  const common::GridLayers* map_{nullptr};
  common::GridLayers handed_out_;  // the worker's copy of the map handed out last

  // frames mapped inline: waiting for their time
  std::deque<MapInput> waiting_;

  // the worker (null: frames are mapped inline when due), the mapper's only user
  std::unique_ptr<common::SerialWorker<MapInput, Done>> worker_;
};

}  // namespace trav::scenarios
