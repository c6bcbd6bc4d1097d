#include "common/grid.h"

#include <algorithm>
#include <cmath>

namespace trav::common {

GridGeometry GridGeometry::Centered(const Eigen::Vector2d& center_W, const Eigen::Vector2d& size_m,
                                    double resolution_m) {
  GridGeometry geometry;
  geometry.resolution_m = resolution_m;
  geometry.num_x = static_cast<int>(std::lround(size_m.x() / resolution_m)) + 1;
  geometry.num_y = static_cast<int>(std::lround(size_m.y() / resolution_m)) + 1;
  geometry.origin_W = center_W - 0.5 * geometry.Extent();
  return geometry;
}

std::optional<Eigen::Vector2i> GridGeometry::CellIndex(const Eigen::Vector2d& p_W) const {
  const Eigen::Vector2d cell = (p_W - origin_W) / resolution_m;
  const int ix = static_cast<int>(std::lround(cell.x()));
  const int iy = static_cast<int>(std::lround(cell.y()));
  if (!Contains(ix, iy)) return std::nullopt;
  return Eigen::Vector2i(ix, iy);
}

float InterpolateBilinear(const GridGeometry& geometry, const Eigen::MatrixXf& layer,
                          const Eigen::Vector2d& p_W) {
  const Eigen::Vector2d cell = (p_W - geometry.origin_W) / geometry.resolution_m;
  const double fx = std::clamp(cell.x(), 0.0, static_cast<double>(geometry.num_x - 1));
  const double fy = std::clamp(cell.y(), 0.0, static_cast<double>(geometry.num_y - 1));
  const int x0 = std::max(0, std::min(static_cast<int>(fx), geometry.num_x - 2));
  const int y0 = std::max(0, std::min(static_cast<int>(fy), geometry.num_y - 2));
  const int x1 = std::min(x0 + 1, geometry.num_x - 1);
  const int y1 = std::min(y0 + 1, geometry.num_y - 1);
  const double tx = fx - x0;
  const double ty = fy - y0;
  const double bottom = (1 - tx) * layer(x0, y0) + tx * layer(x1, y0);
  const double top = (1 - tx) * layer(x0, y1) + tx * layer(x1, y1);
  return static_cast<float>((1 - ty) * bottom + ty * top);
}

}  // namespace trav::common
