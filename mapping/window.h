#pragma once

#include <limits>
#include <utility>

#include <Eigen/Geometry>

#include "common/grid.h"
#include "common/point_cloud.h"
#include "mapping/traversability_mapper.h"

namespace trav::mapping {

/// The valid points of `points_W` in the square window of side `window_m` around the robot, no
/// higher than `max_height_above_m` above its base and, if finite, no higher than
/// `max_height_above_ground_m` above the lowest point of their 1 m column (the local ground: walls
/// and trunks keep only their foot). Counts the input, the NaN or infinite points dropped and the
/// points kept in `result`.
Eigen::Matrix3Xf CropWindow(
    const common::PointCloud& points_W, const Eigen::Vector3d& p_WB, double window_m,
    double max_height_above_m, MapUpdateResult* result,
    double max_height_above_ground_m = std::numeric_limits<double>::infinity());

/// The first and last cell (ix, iy) of the window around the robot on the grid `g`.
std::pair<Eigen::Vector2i, Eigen::Vector2i> WindowCells(const common::GridGeometry& g,
                                                        const Eigen::Vector3d& p_WB,
                                                        double window_m);

}  // namespace trav::mapping
