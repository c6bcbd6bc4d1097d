#include "common/grid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

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

Eigen::Vector2i GridGeometry::NearestLatticeIndex(const Eigen::Vector2d& p_W) const {
  const Eigen::Vector2d cell = (p_W - origin_W) / resolution_m;
  return Eigen::Vector2i(static_cast<int>(std::lround(cell.x())),
                         static_cast<int>(std::lround(cell.y())));
}

std::optional<Eigen::Vector2i> GridGeometry::CellIndex(const Eigen::Vector2d& p_W) const {
  const Eigen::Vector2i index = NearestLatticeIndex(p_W);
  if (!Contains(index.x(), index.y())) return std::nullopt;
  return index;
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

double Roughness(const Eigen::Ref<const Eigen::MatrixXf>& heights_m, int ix, int iy) {
  constexpr int kDirections[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  const auto nx = static_cast<int>(heights_m.rows()), ny = static_cast<int>(heights_m.cols());
  const double z = heights_m(ix, iy);
  double roughness = 0.0;
  for (const auto& d : kDirections) {
    const int ax = ix + d[0], ay = iy + d[1], bx = ix - d[0], by = iy - d[1];
    if (bx < 0 || ax >= nx || std::min(ay, by) < 0 || std::max(ay, by) >= ny) continue;
    const double second = z - 0.5 * (heights_m(ax, ay) + heights_m(bx, by));
    if (std::isfinite(second)) roughness = std::max(roughness, std::abs(second));
  }
  return roughness;
}

GridLayers::GridLayers(const GridGeometry& geometry, const std::vector<std::string>& layer_names)
    : geometry_(geometry) {
  for (const std::string& name : layer_names) AddLayer(name);
}

const Eigen::MatrixXf& GridLayers::Layer(const std::string& layer) const {
  const auto it = layers_.find(layer);
  if (it == layers_.end()) throw std::out_of_range("grid has no layer '" + layer + "'");
  return it->second;
}

Eigen::MatrixXf& GridLayers::Layer(const std::string& layer) {
  const auto it = layers_.find(layer);
  if (it == layers_.end()) throw std::out_of_range("grid has no layer '" + layer + "'");
  return it->second;
}

void GridLayers::AddLayer(const std::string& layer) {
  layers_[layer] = Eigen::MatrixXf::Constant(geometry_.num_x, geometry_.num_y,
                                             std::numeric_limits<float>::quiet_NaN());
}

std::vector<std::string> GridLayers::LayerNames() const {
  std::vector<std::string> names;
  for (const auto& entry : layers_) names.push_back(entry.first);
  return names;
}

std::optional<float> KnownValueAt(const GridGeometry& geometry, const Eigen::MatrixXf& layer,
                                  const Eigen::Vector2d& p_W) {
  const std::optional<Eigen::Vector2i> cell = geometry.CellIndex(p_W);
  if (!cell) return std::nullopt;
  const float value = layer(cell->x(), cell->y());
  if (std::isnan(value)) return std::nullopt;
  return value;
}

std::optional<float> GridLayers::At(const std::string& layer, const Eigen::Vector2d& p_W) const {
  return KnownValueAt(geometry_, Layer(layer), p_W);
}

namespace {

// Shifts `layer` in place so that cell (ix, iy) takes the value of cell (ix + dx, iy + dy), NaN
// where that cell is outside it. Columns (cells of one iy, contiguous) are written in the order
// that reads each source column before it is overwritten: a copy of the layer would cost a second
// pass over all its cells (filling the copy, then swapping), which was 5 % of an eval scene.
void ShiftInPlace(Eigen::MatrixXf* layer, int dx, int dy) {
  const auto nx = static_cast<int>(layer->rows());
  const auto ny = static_cast<int>(layer->cols());
  constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();
  // the cells of a column that have a source: x0 <= ix < x1
  const int x0 = std::clamp(-dx, 0, nx), x1 = std::clamp(nx - dx, x0, nx);
  auto shift_column = [&](int iy) {
    float* to = layer->col(iy).data();
    const int from_y = iy + dy;
    if (from_y < 0 || from_y >= ny || x1 == x0) {
      std::fill(to, to + nx, kUnknown);
      return;
    }
    const float* from = layer->col(from_y).data();
    // memmove: the same column when dy == 0
    std::memmove(to + x0, from + x0 + dx, static_cast<std::size_t>(x1 - x0) * sizeof(float));
    std::fill(to, to + x0, kUnknown);
    std::fill(to + x1, to + nx, kUnknown);
  };
  if (dy >= 0) {
    for (int iy = 0; iy < ny; ++iy) shift_column(iy);
  } else {
    for (int iy = ny - 1; iy >= 0; --iy) shift_column(iy);
  }
}

}  // namespace

Eigen::Vector2i GridGeometry::RecenterShift(const Eigen::Vector2d& center_W) const {
  const Eigen::Vector2d offset = (center_W - Center()) / resolution_m;
  return {static_cast<int>(std::lround(offset.x())), static_cast<int>(std::lround(offset.y()))};
}

GridGeometry GridGeometry::RecenteredOn(const Eigen::Vector2d& center_W) const {
  GridGeometry moved = *this;
  moved.origin_W += resolution_m * RecenterShift(center_W).cast<double>();
  return moved;
}

void GridLayers::Recenter(const Eigen::Vector2d& center_W) {
  const Eigen::Vector2i shift = geometry_.RecenterShift(center_W);
  if (shift.isZero()) return;
  geometry_ = geometry_.RecenteredOn(center_W);
  // new cell (ix, iy) was old cell (ix + dx, iy + dy)
  for (auto& entry : layers_) ShiftInPlace(&entry.second, shift.x(), shift.y());
}

}  // namespace trav::common
