#pragma once

#include <string>

#include <Eigen/Core>

#include "common/grid.h"

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

}  // namespace trav::planner::test_util
