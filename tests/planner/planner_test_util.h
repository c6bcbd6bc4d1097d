#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/grid.h"
#include "common/trajectory.h"

namespace trav::planner::test_util {

// Sets the cost of every cell whose centre satisfies `inside` on the "traversability" layer.
template <typename Inside>
void Paint(common::GridLayers* map, float value, Inside inside) {
  const common::GridGeometry& g = map->geometry();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      if (inside(g.CellCenter(ix, iy))) map->Layer("traversability")(ix, iy) = value;
    }
  }
}

// Adds (or overwrites) `map`'s "roughness" layer with common::Roughness of the heights
// `height_m(p_W)` [m] at the cells' centres, as the mappers compute it from their points.
template <typename Height>
void PaintRoughness(common::GridLayers* map, Height height_m) {
  const common::GridGeometry& g = map->geometry();
  Eigen::MatrixXf heights(g.num_x, g.num_y);
  for (int iy = 0; iy < g.num_y; ++iy) {
    for (int ix = 0; ix < g.num_x; ++ix) {
      heights(ix, iy) = static_cast<float>(height_m(g.CellCenter(ix, iy)));
    }
  }
  if (!map->Has("roughness")) map->AddLayer("roughness");
  for (int iy = 0; iy < g.num_y; ++iy) {
    for (int ix = 0; ix < g.num_x; ++ix) {
      map->Layer("roughness")(ix, iy) = static_cast<float>(common::Roughness(heights, ix, iy));
    }
  }
}

// A drive from (0, 0) heading +x at `v_m_s` from t0_s for `duration_s`, sampled every 0.01 s: at
// yaw rate `turn_rad_s` over its first `turn_m` metres, then straight (the midpoint rule at
// 1 ms).
inline common::Trajectory TurnThenStraight(double t0_s, double v_m_s, double turn_m,
                                           double turn_rad_s, double duration_s) {
  std::vector<common::TrajectoryPoint> points;
  common::TrajectoryPoint p;
  p.t_s = t0_s;
  p.v = v_m_s;
  double travelled_m = 0.0;
  const int steps = static_cast<int>(std::lround(duration_s / 1e-3));
  for (int k = 0; k <= steps; ++k) {
    p.omega = travelled_m < turn_m ? turn_rad_s : 0.0;
    if (k % 10 == 0) points.push_back(p);
    const double mid_yaw = p.yaw + 0.5e-3 * p.omega;
    p.position_W += 1e-3 * v_m_s * Eigen::Vector2d(std::cos(mid_yaw), std::sin(mid_yaw));
    p.yaw += 1e-3 * p.omega;
    p.t_s = t0_s + (k + 1) * 1e-3;
    travelled_m += 1e-3 * v_m_s;
  }
  return common::Trajectory(std::move(points));
}

}  // namespace trav::planner::test_util
