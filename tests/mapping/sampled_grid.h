#pragma once

#include <functional>

#include <Eigen/Core>

#include "common/grid.h"

namespace trav::mapping::test_util {

/// `value(x, y)` at every cell centre of `grid`, as a layer (num_x, num_y).
inline Eigen::MatrixXf Sampled(const common::GridGeometry& grid,
                               const std::function<double(double, double)>& value) {
  Eigen::MatrixXf layer(grid.num_x, grid.num_y);
  for (int ix = 0; ix < grid.num_x; ++ix) {
    for (int iy = 0; iy < grid.num_y; ++iy) {
      const Eigen::Vector2d p = grid.CellCenter(ix, iy);
      layer(ix, iy) = static_cast<float>(value(p.x(), p.y()));
    }
  }
  return layer;
}

}  // namespace trav::mapping::test_util
