#pragma once

#include <string>

#include "common/point_cloud.h"
#include "sim/lidar/lidar_emulator.h"

namespace trav::scenarios {

/// Writes a cloud as binary PCD with fields x, y, z (PCL). @throws std::runtime_error on failure.
void WritePcd(const std::string& path, const common::PointCloud& cloud);

/// Writes a LiDAR frame as binary PCD with fields x, y, z (in L), `time` (offset after the frame
/// stamp [s]), `line`, `reflectivity` (Livox's 0..255 scale) and `tag`; the viewpoint is the
/// frame-start sensor pose.
/// @throws std::runtime_error on failure.
void WriteLidarFramePcd(const std::string& path, const lidar::LidarFrame& frame);

}  // namespace trav::scenarios
