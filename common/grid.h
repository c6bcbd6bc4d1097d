#pragma once

#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace trav::common {

/// Geometry of a regular 2-D grid in the world frame W. Cell (ix, iy) is centred at
/// origin_W + resolution_m * (ix, iy); ix runs along +x, iy along +y. Layers on this grid are
/// `Eigen::MatrixXf` of size (num_x, num_y), indexed (ix, iy); NaN marks an unknown cell.
///
/// Column-major storage puts (ix, iy) at ix + iy * num_x: row-major with rows along y, which is the
/// layout of a MuJoCo height field and of an image with +y as its row direction.
struct GridGeometry {
  Eigen::Vector2d origin_W{Eigen::Vector2d::Zero()};  ///< centre of cell (0, 0) [m]
  double resolution_m{0.1};                           ///< cell size [m]
  int num_x{0};                                       ///< cells along x
  int num_y{0};                                       ///< cells along y

  /// Grid of `size_m` (x, y) [m] centred on `center_W` with cells of `resolution_m`; the cell
  /// centres include both borders, so it has round(size / resolution) + 1 cells along each axis.
  static GridGeometry Centered(const Eigen::Vector2d& center_W, const Eigen::Vector2d& size_m,
                               double resolution_m);

  /// Centre of cell (ix, iy) in W [m].
  Eigen::Vector2d CellCenter(int ix, int iy) const {
    return origin_W + resolution_m * Eigen::Vector2d(ix, iy);
  }

  /// Extent between the first and the last cell centre along x and y [m].
  Eigen::Vector2d Extent() const { return resolution_m * Eigen::Vector2d(num_x - 1, num_y - 1); }

  /// Centre of the grid in W [m].
  Eigen::Vector2d Center() const { return origin_W + 0.5 * Extent(); }

  /// The cell whose centre is nearest to p_W, or nothing if p_W lies outside the grid.
  std::optional<Eigen::Vector2i> CellIndex(const Eigen::Vector2d& p_W) const;
  /// The indices (ix, iy) of the cell centre nearest to p_W on the grid's lattice extended beyond
  /// the grid (CellIndex's, without the bounds).
  Eigen::Vector2i NearestLatticeIndex(const Eigen::Vector2d& p_W) const;

  /// True if (ix, iy) is a cell of the grid.
  bool Contains(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < num_x && iy < num_y; }

  /// True if both grids have the same cells: origin, resolution and counts, exactly.
  bool operator==(const GridGeometry& other) const {
    return origin_W == other.origin_W && resolution_m == other.resolution_m &&
           num_x == other.num_x && num_y == other.num_y;
  }
  bool operator!=(const GridGeometry& other) const { return !(*this == other); }

  /// The whole cells (dx, dy) that bring the grid's centre nearest to center_W.
  Eigen::Vector2i RecenterShift(const Eigen::Vector2d& center_W) const;
  /// The grid moved by RecenterShift(center_W): the geometry GridLayers::Recenter gives.
  GridGeometry RecenteredOn(const Eigen::Vector2d& center_W) const;
};

/// True if `predicate(ix, iy)` holds for a cell of `geometry` whose centre lies within `radius_m`
/// of p_W (cells visited along y within x, from the lowest index); false if p_W is off the grid.
template <typename Predicate>
bool AnyCellWithin(const GridGeometry& geometry, const Eigen::Vector2d& p_W, double radius_m,
                   Predicate&& predicate) {
  const std::optional<Eigen::Vector2i> centre = geometry.CellIndex(p_W);
  if (!centre) return false;
  const int reach = static_cast<int>(std::ceil(radius_m / geometry.resolution_m));
  for (int ix = centre->x() - reach; ix <= centre->x() + reach; ++ix) {
    for (int iy = centre->y() - reach; iy <= centre->y() + reach; ++iy) {
      if (!geometry.Contains(ix, iy) || (geometry.CellCenter(ix, iy) - p_W).norm() > radius_m) {
        continue;
      }
      if (predicate(ix, iy)) return true;
    }
  }
  return false;
}

/// The value of `layer` (on `geometry`) in the cell containing p_W, or nothing outside the grid or
/// if unknown (NaN).
std::optional<float> KnownValueAt(const GridGeometry& geometry, const Eigen::MatrixXf& layer,
                                  const Eigen::Vector2d& p_W);

/// Bilinear interpolation of `layer` (on `geometry`) at p_W, clamped to the grid's border.
float InterpolateBilinear(const GridGeometry& geometry, const Eigen::MatrixXf& layer,
                          const Eigen::Vector2d& p_W);

/// The roughness of cell (ix, iy) of a grid of heights [m]: the largest second difference
/// |z - (z_a + z_b) / 2| over its opposite neighbours a, b along x, y and both diagonals whose
/// three heights are finite (0 if none): 0 on any plane whatever its slope, about half the height
/// at the edge of a step, a stair or a curb, and res tan(change of slope) / 2 at a crest.
double Roughness(const Eigen::Ref<const Eigen::MatrixXf>& heights_m, int ix, int iy);

/// Named layers on one grid geometry: traversability maps, elevation maps and ground truth are all
/// GridLayers. Every layer is an `Eigen::MatrixXf` of size (num_x, num_y) indexed (ix, iy); NaN
/// marks an unknown cell. A copyable value.
class GridLayers {
 public:
  GridLayers() = default;
  /// A grid with `layer_names`, every cell unknown (NaN).
  GridLayers(const GridGeometry& geometry, const std::vector<std::string>& layer_names);

  const GridGeometry& geometry() const { return geometry_; }

  /// True if the layer exists.
  bool Has(const std::string& layer) const { return layers_.count(layer) > 0; }

  /// The layer. @throws std::out_of_range naming the layer if it does not exist.
  const Eigen::MatrixXf& Layer(const std::string& layer) const;
  Eigen::MatrixXf& Layer(const std::string& layer);

  /// Adds a layer of unknown cells (or resets it if it exists).
  void AddLayer(const std::string& layer);

  /// Names of the layers, sorted.
  std::vector<std::string> LayerNames() const;

  /// The value of `layer` in the cell containing p_W, or nothing outside the grid or if unknown
  /// (KnownValueAt on the layer found by name: in a loop, find the layer once instead).
  std::optional<float> At(const std::string& layer, const Eigen::Vector2d& p_W) const;

  /// Moves the grid so that it is centred (to the nearest cell) on `center_W`, keeping every cell
  /// anchored in the world: cells that stay in the grid keep their values, cells that enter it are
  /// unknown. Costs O(cells); allocates nothing.
  void Recenter(const Eigen::Vector2d& center_W);

 private:
  GridGeometry geometry_{};
  std::map<std::string, Eigen::MatrixXf> layers_;
};

}  // namespace trav::common
