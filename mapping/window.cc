#include "mapping/window.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

namespace trav::mapping {
namespace {

// A cell's own span counts as a step where no point of its neighbourhood lies more than this below
// the cell's lowest point (less the ground plane's rise): along a face whose foot the sensor does
// not see, the lowest beam meets neighbouring cells at heights that the scan pattern's sampling
// scatters. With none allowed, `hard/low_wall` driven with a 0.15 m clearance lost the wall seen
// from close by and hit it at 0.9 m/s; with 2 cm it passes at 0.1 and 0.15 m, and the robot of
// `probes/forest_backwards` at seed 1 keeps the side of the trunk it touched.
constexpr float kFootTolerance_m = 0.02f;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A tall face's points are those of its cell more than this above the cell's lowest point (plus
// the ground plane's rise across the cell): the ground at its foot lies within the points' noise of
// the lowest (under 1 cm in height at the grazing angles the ground is seen at). The box of only
// the cell's upper half of points left out the foot of a box leaning 11 deg (`hard/low_wall` at
// LiDAR seed 16, whose robot then touched it).
constexpr float kFacePoint_m = 0.05f;
// How far before a drop's edge the ground's fall toward it is measured [m].
constexpr double kApproach_m = 1.0;

// The ground plane's rise across a cell's diagonal where its gradient is `gradient` (dz/dx, dz/dy):
// how far apart in height two points of one cell of bare ground can lie [m].
float RiseAcrossCell(double resolution_m, const Eigen::Vector2f& gradient) {
  return static_cast<float>(std::sqrt(2.0) * resolution_m) * gradient.norm();
}

// True if cell (ix, iy), whose highest point in the frame is `top`, is a step against the lowest
// points the cells ever showed (`floor`, NaN where none), on ground of gradient `gradient`: its top
// stands more than `max_step_m` above its own floor, or its floor more than that above a side
// neighbour's, besides the ground plane's rise across a cell (and between the two cells). The
// first is a low wall whose foot was seen from farther away and now lies in the blind zone, its
// face seen from close by only up from where the lowest beam meets it; the second a face whose
// foot its cell never showed (a box leaning over it) beside ground seen before.
bool StepAboveFloors(const Eigen::MatrixXf& floor, int ix, int iy, float top,
                     const Eigen::Vector2f& gradient, double resolution_m, double max_step_m) {
  const float own = floor(ix, iy);
  const float within = RiseAcrossCell(resolution_m, gradient);
  if (top - own - within > max_step_m) return true;
  const auto resolution = static_cast<float>(resolution_m);
  const std::array<Eigen::Vector2i, 4> sides{{{-1, 0}, {1, 0}, {0, -1}, {0, 1}}};
  for (const Eigen::Vector2i& d : sides) {
    const int jx = ix + d.x(), jy = iy + d.y();
    if (jx < 0 || jy < 0 || jx >= floor.rows() || jy >= floor.cols()) continue;
    // (NaN, a neighbour without a floor, compares false)
    const float rise = -resolution * (gradient.x() * static_cast<float>(d.x()) +
                                      gradient.y() * static_cast<float>(d.y()));
    if (own - (floor(jx, jy) + rise) - within > max_step_m) return true;
  }
  return false;
}

// True if `highest`(ix, iy) stands more than `max_bump_m` above the highest points of both cells
// k = 1 or 2 away on either side of it along x, y or a diagonal, each raised by `rise` (the ground
// plane's rise from that cell to this one): a bump the robot would straddle. (Their highest
// points, not their lowest: along the edge of a curb the cells hold ground too.)
template <typename View, typename Rise>
bool IsBump(const View& highest, int ix, int iy, double max_bump_m, const Rise& rise) {
  constexpr std::array<std::array<int, 2>, 4> kAxes{{{1, 0}, {0, 1}, {1, 1}, {1, -1}}};
  const auto nx = static_cast<int>(highest.rows()), ny = static_cast<int>(highest.cols());
  auto top = [&](int jx, int jy) {
    return jx < 0 || jy < 0 || jx >= nx || jy >= ny || std::isinf(highest(jx, jy))
               ? std::numeric_limits<float>::infinity()
               : highest(jx, jy) + rise(jx, jy);
  };
  for (const auto& a : kAxes) {
    for (int k = 1; k <= 2; ++k) {
      const float higher_side =
          std::max(top(ix - k * a[0], iy - k * a[1]), top(ix + k * a[0], iy + k * a[1]));
      if (highest(ix, iy) - higher_side > max_bump_m) return true;
    }
  }
  return false;
}

// The layers of a map that hold each cell's faces over time, and the rules that read them.
struct FaceHistory {
  explicit FaceHistory(common::GridLayers* map)
      : obstacle(map->Layer(layers::kObstacle)),
        seen_s(map->Layer(layers::kObstacleSeen)),
        since_s(map->Layer(layers::kObstacleSince)),
        free_since_s(map->Layer(layers::kFreeSince)),
        extent{&map->Layer(layers::kFaceXLow), &map->Layer(layers::kFaceXHigh),
               &map->Layer(layers::kFaceYLow), &map->Layer(layers::kFaceYHigh)} {}

  // True if points showed the face of cell (ix, iy) for `memory_s` (> 0) or longer: the world's.
  // Without a memory no face is forgotten and none is lasting: the first free points clear it.
  bool Lasting(int ix, int iy, double memory_s) const {
    return memory_s > 0.0 && seen_s(ix, iy) - since_s(ix, iy) >= memory_s;
  }

  // Records what the points of t_s showed of cell (ix, iy): a face (1) or free ground (0). The
  // latest reading decides, but that a lasting face stays until the cell has shown free for
  // `area.obstacle_clear_s`. A face's extent is the union of the boxes (x_low, x_high, y_low,
  // y_high) of the readings of its unbroken run that have one (NaN: none, a step's or a drop's);
  // the whole cell (NaN) until one has; a cell seen free has none.
  void Observe(int ix, int iy, float face, double t_s, const MapArea& area,
               const Eigen::Vector4f& box) {
    const bool was_face = obstacle(ix, iy) == 1.0f;
    const auto t = static_cast<float>(t_s);
    if (face == 1.0f) {
      if (obstacle(ix, iy) != 1.0f) since_s(ix, iy) = t;
      seen_s(ix, iy) = t;
      free_since_s(ix, iy) = kNaN;
    } else if (std::isnan(free_since_s(ix, iy))) {
      free_since_s(ix, iy) = t;
    }
    const bool stays = obstacle(ix, iy) == 1.0f && Lasting(ix, iy, area.obstacle_memory_s) &&
                       t_s - free_since_s(ix, iy) < area.obstacle_clear_s;
    if (!stays) obstacle(ix, iy) = face;
    if (obstacle(ix, iy) != 1.0f) {
      SetExtent(ix, iy, Eigen::Vector4f::Constant(kNaN));
    } else if (face == 1.0f && (!was_face || std::isnan((*extent[0])(ix, iy)))) {
      SetExtent(ix, iy, box);
    } else if (face == 1.0f && !box.hasNaN()) {
      const Eigen::Vector4f old = Extent(ix, iy);
      SetExtent(ix, iy,
                Eigen::Vector4f(std::min(old(0), box(0)), std::max(old(1), box(1)),
                                std::min(old(2), box(2)), std::max(old(3), box(3))));
    }
  }

  // Forgets the face of cell (ix, iy): its obstacle becomes unknown (its extent stays: where the
  // cost the face left is lethal, the face lay there).
  void Forget(int ix, int iy) { obstacle(ix, iy) = kNaN; }

  // True if cell (ix, iy), unseen at t_s, holds a face to forget (`area.obstacle_memory_s` > 0):
  // one shown for less than the memory, and not shown for longer than that since, beside no face
  // that lasts or that was shown after it. The end of a wall seen along its length shows free
  // ground from afar and its face only from close by, for well under the memory, then lies in the
  // blind zone; the wall's faces beside it are shown after it or last (`hard/low_wall` at LiDAR
  // seeds 21 and 37 forgot such an end and drove into it). A walker's trail of faces is forgotten
  // once the faces shown after each of its cells are (in the same frame where the scan reaches
  // them first, else in the next).
  bool Forgettable(int ix, int iy, double t_s, const MapArea& area) const {
    return obstacle(ix, iy) == 1.0f && area.obstacle_memory_s > 0.0 &&
           t_s - seen_s(ix, iy) > area.obstacle_memory_s &&
           !Lasting(ix, iy, area.obstacle_memory_s) &&
           !BesideAFaceThatOutlastsIt(ix, iy, area.obstacle_memory_s);
  }

  // True if a side or diagonal neighbour of cell (ix, iy) holds a face that lasts or that points
  // showed after the cell's.
  bool BesideAFaceThatOutlastsIt(int ix, int iy, double memory_s) const {
    for (int jx = std::max(0, ix - 1); jx <= std::min<int>(obstacle.rows() - 1, ix + 1); ++jx) {
      for (int jy = std::max(0, iy - 1); jy <= std::min<int>(obstacle.cols() - 1, iy + 1); ++jy) {
        if ((jx != ix || jy != iy) && obstacle(jx, jy) == 1.0f &&
            (Lasting(jx, jy, memory_s) || seen_s(jx, jy) > seen_s(ix, iy)))
          return true;
      }
    }
    return false;
  }

  Eigen::MatrixXf& obstacle;      // 1 face, 0 free, NaN unknown
  Eigen::MatrixXf& seen_s;        // the latest points that showed the face [s]
  Eigen::MatrixXf& since_s;       // the first of their unbroken run [s]
  Eigen::MatrixXf& free_since_s;  // the first of the latest unbroken run of free readings [s]
  // the face's box in its cell: x_low, x_high, y_low, y_high from the centre [m]
  std::array<Eigen::MatrixXf*, 4> extent;

  Eigen::Vector4f Extent(int ix, int iy) const {
    return {(*extent[0])(ix, iy), (*extent[1])(ix, iy), (*extent[2])(ix, iy), (*extent[3])(ix, iy)};
  }
  void SetExtent(int ix, int iy, const Eigen::Vector4f& box) {
    for (int k = 0; k < 4; ++k) (*extent[k])(ix, iy) = box(k);
  }
};

}  // namespace

void WindowCrop::Crop(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB,
                      double window_m, double max_height_above_m, double max_height_above_ground_m,
                      MapUpdateResult* result) {
  const double half = 0.5 * window_m;
  Eigen::Index kept = 0;
  auto below_robot = below_robot_.Resize(3, points_W.size());
  for (Eigen::Index i = 0; i < points_W.size(); ++i) {
    const Eigen::Vector3f p = points_W.points.col(i);
    if (!p.allFinite()) {
      ++result->dropped_invalid;
      continue;
    }
    if (std::abs(p.x() - p_WB.x()) <= half && std::abs(p.y() - p_WB.y()) <= half &&
        p.z() <= p_WB.z() + max_height_above_m) {
      below_robot.col(kept++) = p;
    }
  }
  below_robot_.Resize(3, kept);
  auto window = window_.Resize(3, kept);
  column_lowest_.clear();
  column_plane_.clear();
  if (!std::isfinite(max_height_above_ground_m) || kept == 0) {
    window = below_robot_.view();
  } else {
    // the lowest point of each 1 m column stands for the ground there, with the plane through
    // the lowest points of its 3 x 3 columns
    p_WB_ = p_WB;
    half_window_m_ = half;
    columns_ = std::max(1, static_cast<int>(std::ceil(window_m / kColumn_m - 1e-9)));
    const Eigen::Vector3f no_point(0.0f, 0.0f, std::numeric_limits<float>::infinity());
    column_lowest_.assign(static_cast<std::size_t>(columns_ * columns_), no_point);
    column_plane_.resize(column_lowest_.size());
    const auto all = below_robot_.view();
    for (Eigen::Index i = 0; i < kept; ++i) {
      Eigen::Vector3f& lowest = column_lowest_[ColumnOf(all(0, i), all(1, i))];
      if (all(2, i) < lowest.z()) lowest = all.col(i);
    }
    for (int cx = 0; cx < columns_; ++cx) {
      for (int cy = 0; cy < columns_; ++cy) {
        column_plane_[static_cast<std::size_t>(cy * columns_ + cx)] = GroundPlane(cx, cy);
      }
    }
    const auto x_B = static_cast<float>(p_WB.x()), y_B = static_cast<float>(p_WB.y());
    Eigen::Index low = 0;
    for (Eigen::Index i = 0; i < kept; ++i) {
      const Eigen::Vector3f p = all.col(i);
      const std::size_t c = ColumnOf(p.x(), p.y());
      const Eigen::Vector3f& plane = column_plane_[c];
      const float ground = std::max(
          column_lowest_[c].z(), plane.x() + plane.y() * (p.x() - x_B) + plane.z() * (p.y() - y_B));
      if (p.z() <= ground + max_height_above_ground_m) window.col(low++) = p;
    }
    window_.Resize(3, low);
  }
  result->input_points = static_cast<int>(points_W.size());
  result->window_points = static_cast<int>(window_.cols());
}

void WindowCrop::KeepNearFloor(const common::GridLayers& map, double max_above_floor_m) {
  if (!std::isfinite(max_above_floor_m)) return;
  const common::GridGeometry& g = map.geometry();
  const Eigen::MatrixXf& floor = map.Layer(layers::kFloor);
  const auto above = static_cast<float>(max_above_floor_m);
  auto window = window_.view();
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < window.cols(); ++i) {
    const Eigen::Vector3f p = window.col(i);
    const Eigen::Vector2d p_W = p.head<2>().cast<double>();
    const std::optional<Eigen::Vector2i> cell = g.CellIndex(p_W);
    // (a cell without a floor, NaN, keeps its points)
    if (cell && p.z() > floor(cell->x(), cell->y()) + above +
                            RiseAcrossCell(g.resolution_m, GroundGradient(p_W)))
      continue;
    window.col(kept++) = p;
  }
  window_.Resize(3, kept);
}

common::ScratchMatrix<float>::ConstView ObstacleMarker::Cells(
    const Eigen::Ref<const Eigen::Matrix3Xf>& points_W, const common::GridGeometry& g,
    const Eigen::Vector2i& low, const Eigen::Vector2i& high, double min_span_m, double max_step_m,
    double max_bump_m, const WindowCrop* ground, const Eigen::MatrixXf* floor) {
  const Eigen::Vector2i size = high - low + Eigen::Vector2i::Ones();
  auto lowest = lowest_.Resize(size.x(), size.y());
  auto highest = highest_.Resize(size.x(), size.y());
  lowest.setConstant(std::numeric_limits<float>::infinity());
  highest.setConstant(-std::numeric_limits<float>::infinity());
  // each point's cell, indexed from `low` (-1 outside low to high), kept for the faces' boxes
  point_cells_.resize(static_cast<std::size_t>(points_W.cols()));
  for (Eigen::Index i = 0; i < points_W.cols(); ++i) {
    Eigen::Vector2i& local = point_cells_[static_cast<std::size_t>(i)];
    local.setConstant(-1);
    const std::optional<Eigen::Vector2i> cell =
        g.CellIndex(points_W.col(i).head<2>().cast<double>());
    if (!cell) continue;
    const Eigen::Vector2i from_low = *cell - low;
    if ((from_low.array() < 0).any() || (from_low.array() >= size.array()).any()) continue;
    local = from_low;
    lowest(local.x(), local.y()) = std::min(lowest(local.x(), local.y()), points_W(2, i));
    highest(local.x(), local.y()) = std::max(highest(local.x(), local.y()), points_W(2, i));
  }
  // each cell's highest point against the lowest of its 3 x 3 neighbourhood (the ground beside a
  // face: sparse points high on a wall still read as a wall)
  auto cells = cells_.Resize(size.x(), size.y());
  cells.setConstant(std::numeric_limits<float>::quiet_NaN());
  auto roughness = roughness_.Resize(size.x(), size.y());
  roughness.setConstant(std::numeric_limits<float>::quiet_NaN());
  // per cell, the height above which its points are a tall face's (infinity: no tall face)
  auto face_floor = face_floor_.Resize(size.x(), size.y());
  face_floor.setConstant(std::numeric_limits<float>::infinity());
  const auto resolution = static_cast<float>(g.resolution_m);
  for (int ix = 0; ix < size.x(); ++ix) {
    for (int iy = 0; iy < size.y(); ++iy) {
      if (std::isinf(lowest(ix, iy))) continue;
      // the ground plane's slope here, and its rise from cell (jx, jy) to this one
      const Eigen::Vector2f slope =
          ground != nullptr ? ground->GroundGradient(g.CellCenter(low.x() + ix, low.y() + iy))
                            : Eigen::Vector2f::Zero();
      auto rise = [&](int jx, int jy) {
        return resolution *
               (slope.x() * static_cast<float>(ix - jx) + slope.y() * static_cast<float>(iy - jy));
      };
      float foot = lowest(ix, iy);
      for (int jx = std::max(0, ix - 1); jx <= std::min(size.x() - 1, ix + 1); ++jx) {
        for (int jy = std::max(0, iy - 1); jy <= std::min(size.y() - 1, iy + 1); ++jy) {
          foot = std::min(foot, lowest(jx, jy) + rise(jx, jy));
        }
      }
      // (the ground plane's rise across the cell)
      const float within = RiseAcrossCell(g.resolution_m, slope);
      // the lowest point the cell showed before (NaN: none, or no floor given; compares false)
      const float floor_here = floor != nullptr ? (*floor)(low.x() + ix, low.y() + iy) : kNaN;
      // a face that stands out of its neighbourhood, or out of the ground its cell showed before
      // (a jamb's end, a few centimetres of which fill a cell whose ground lies in the blind zone)
      bool face = highest(ix, iy) - foot > min_span_m || highest(ix, iy) - floor_here > min_span_m;
      if (face) {
        // a cell that shows no ground now: every point of it is the face's
        face_floor(ix, iy) = lowest(ix, iy) - floor_here > kFacePoint_m + within
                                 ? -std::numeric_limits<float>::infinity()
                                 : lowest(ix, iy) + kFacePoint_m + within;
      }
      // a step above a side neighbour's top (a neighbour without points, at -infinity, is skipped),
      // or within a cell that holds its neighbourhood's lowest point (to kFootTolerance_m): a face
      // whose foot the sensor does not see (a low wall just ahead, whose lowest points are where
      // the lowest beam meets it, no ground beside them; rubble on a slope has lower ground beside
      // it)
      if (max_step_m > 0.0) {
        face = face || (lowest(ix, iy) <= foot + kFootTolerance_m &&
                        highest(ix, iy) - lowest(ix, iy) - within > max_step_m);
        const std::array<Eigen::Vector2i, 4> sides{
            {{ix - 1, iy}, {ix + 1, iy}, {ix, iy - 1}, {ix, iy + 1}}};
        for (const Eigen::Vector2i& n : sides) {
          if ((n.array() < 0).any() || n.x() >= size.x() || n.y() >= size.y() ||
              std::isinf(highest(n.x(), n.y())))
            continue;
          face =
              face || highest(ix, iy) - (highest(n.x(), n.y()) + rise(n.x(), n.y())) > max_step_m;
        }
      }
      if (max_bump_m > 0.0 && !face) face = IsBump(highest, ix, iy, max_bump_m, rise);
      cells(ix, iy) = face ? 1.0f : 0.0f;
      roughness(ix, iy) = static_cast<float>(common::Roughness(highest, ix, iy));
    }
  }
  BoxFaces(points_W, g, low);
  return cells_.const_view();
}

void ObstacleMarker::BoxFaces(const Eigen::Ref<const Eigen::Matrix3Xf>& points_W,
                              const common::GridGeometry& g, const Eigen::Vector2i& low) {
  // each tall face's box of its points; a lower step's points (its top seen at grazing angles, its
  // face in the blind zone once near) do not bound it: none
  const auto face_floor = face_floor_.const_view();
  const auto nx = face_floor.rows();
  auto extents = extents_.Resize(4, nx * face_floor.cols());
  extents.setConstant(kNaN);
  for (Eigen::Index i = 0; i < points_W.cols(); ++i) {
    const Eigen::Vector2i& cell = point_cells_[static_cast<std::size_t>(i)];
    if (cell.x() < 0 || points_W(2, i) <= face_floor(cell.x(), cell.y())) continue;
    const Eigen::Vector2f offset =
        points_W.col(i).head<2>() -
        g.CellCenter(low.x() + cell.x(), low.y() + cell.y()).cast<float>();
    auto box = extents.col(cell.x() + nx * cell.y());
    box(0) = std::fmin(box(0), offset.x());
    box(1) = std::fmax(box(1), offset.x());
    box(2) = std::fmin(box(2), offset.y());
    box(3) = std::fmax(box(3), offset.y());
  }
}

std::size_t WindowCrop::ColumnOf(double x_m, double y_m) const {
  const int cx =
      std::clamp(static_cast<int>((x_m - p_WB_.x() + half_window_m_) / kColumn_m), 0, columns_ - 1);
  const int cy =
      std::clamp(static_cast<int>((y_m - p_WB_.y() + half_window_m_) / kColumn_m), 0, columns_ - 1);
  return static_cast<std::size_t>(cy * columns_ + cx);
}

Eigen::Vector2f WindowCrop::GroundGradient(const Eigen::Vector2d& p_W) const {
  if (column_plane_.empty()) return Eigen::Vector2f::Zero();
  const Eigen::Vector3f& plane = column_plane_[ColumnOf(p_W.x(), p_W.y())];
  return std::isinf(plane.x()) ? Eigen::Vector2f::Zero() : Eigen::Vector2f(plane.tail<2>());
}

Eigen::Vector3f WindowCrop::GroundPlane(int cx, int cy) const {
  // least squares over the lowest points, about the robot (float-safe coordinates)
  constexpr double kMaxGradient = 1.0;  // tan 45 deg: steeper than the robot drives (40 deg)
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  int n = 0;
  for (int jx = std::max(0, cx - 1); jx <= std::min(columns_ - 1, cx + 1); ++jx) {
    for (int jy = std::max(0, cy - 1); jy <= std::min(columns_ - 1, cy + 1); ++jy) {
      const Eigen::Vector3f& q = column_lowest_[static_cast<std::size_t>(jy * columns_ + jx)];
      if (std::isinf(q.z())) continue;
      const Eigen::Vector3d a(1.0, q.x() - p_WB_.x(), q.y() - p_WB_.y());
      normal += a * a.transpose();
      rhs += a * static_cast<double>(q.z());
      ++n;
    }
  }
  // fewer than three points, or all on a line: no plane (the column's lowest point alone)
  const Eigen::Vector3f none(-std::numeric_limits<float>::infinity(), 0.0f, 0.0f);
  if (n < 3) return none;
  const Eigen::LDLT<Eigen::Matrix3d> solver(normal);
  if (solver.info() != Eigen::Success || solver.rcond() < 1e-6) return none;
  Eigen::Vector3d c = solver.solve(rhs);
  const double gradient = c.tail<2>().norm();
  if (gradient > kMaxGradient) c.tail<2>() *= kMaxGradient / gradient;
  return c.cast<float>();
}

std::pair<Eigen::Vector2i, Eigen::Vector2i> WindowCells(const common::GridGeometry& g,
                                                        const Eigen::Vector3d& p_WB,
                                                        double window_m) {
  const Eigen::Vector2d corner = Eigen::Vector2d::Constant(0.5 * window_m);
  return {*g.CellIndex(g.origin_W.cwiseMax(p_WB.head<2>() - corner)),
          *g.CellIndex((g.origin_W + g.Extent()).cwiseMin(p_WB.head<2>() + corner))};
}

void ObstacleMarker::CloseMask() {
  const Eigen::Index nx = mask_.rows(), ny = mask_.cols();
  // each cell the "or" (dilation) or the "and" (erosion) of its 3 x 3 neighbourhood in `in`
  auto neighbourhood = [&](const auto& in, bool all, auto out) {
    for (Eigen::Index ix = 0; ix < nx; ++ix) {
      for (Eigen::Index iy = 0; iy < ny; ++iy) {
        bool value = all;
        for (Eigen::Index jx = std::max<Eigen::Index>(0, ix - 1); jx <= std::min(nx - 1, ix + 1);
             ++jx) {
          for (Eigen::Index jy = std::max<Eigen::Index>(0, iy - 1); jy <= std::min(ny - 1, iy + 1);
               ++jy) {
            value = all ? (value && in(jx, jy) != 0) : (value || in(jx, jy) != 0);
          }
        }
        out(ix, iy) = value ? 1 : 0;
      }
    }
  };
  neighbourhood(mask_.view(), false, dilated_.Resize(nx, ny));
  neighbourhood(dilated_.view(), true, closed_.Resize(nx, ny));
}

common::ScratchMatrix<std::uint8_t>::ConstView ObstacleMarker::Drops(const common::GridGeometry& g,
                                                                     const MapArea& area,
                                                                     const Eigen::Vector3d& p_WB) {
  const auto lowest = lowest_.const_view();
  const auto highest = highest_.const_view();
  const auto cells = cells_.const_view();
  const Eigen::Vector2i size(static_cast<int>(highest.rows()), static_cast<int>(highest.cols()));
  auto drops = drops_.Resize(size.x(), size.y());
  drops.setZero();
  if (!(area.drop_gap_m > 0.0)) return drops_.const_view();
  const double min_slope = std::tan(area.drop_slope_deg * M_PI / 180.0);
  constexpr std::array<std::array<int, 2>, 8> kDirections{
      {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}}};
  auto inside = [&](const Eigen::Vector2i& c) {
    return (c.array() >= 0).all() && (c.array() < size.array()).all();
  };
  for (int ix = 0; ix < size.x(); ++ix) {
    for (int iy = 0; iy < size.y(); ++iy) {
      // no point, a face, or above the robot's reach: the robot would not drive off it (the top
      // of a box, whose shadow is no drop for a robot on the ground)
      if (cells(ix, iy) != 0.0f || lowest(ix, iy) > p_WB.z() + area.max_step_m) continue;
      for (const auto& direction : kDirections) {
        const Eigen::Vector2i d(direction[0], direction[1]);
        // an edge of seen ground: the cell behind it on the line is ground too, at its height
        // (not a lone point on a trunk or a stone above unseen cells)
        const Eigen::Vector2i behind(ix - d.x(), iy - d.y());
        if (!inside(behind) || cells(behind.x(), behind.y()) != 0.0f ||
            std::abs(lowest(ix, iy) - lowest(behind.x(), behind.y())) > area.max_step_m) {
          continue;
        }
        const double step_m = g.resolution_m * d.cast<double>().norm();
        // the ground's fall along the line up to the edge, from the farthest cell of ground as far
        // back as kApproach_m: a hillside the robot drives down falls on beyond the edge at that
        // rate (up to the drop slope's); measured only for a gap that ends at ground
        auto fall = [&] {
          for (int k = static_cast<int>(kApproach_m / step_m + 1e-9); k >= 1; --k) {
            const Eigen::Vector2i back(ix - k * d.x(), iy - k * d.y());
            if (inside(back) && cells(back.x(), back.y()) == 0.0f) {
              const double rate = (lowest(back.x(), back.y()) - lowest(ix, iy)) / (k * step_m);
              return std::clamp(rate, 0.0, min_slope);
            }
          }
          return 0.0;
        };
        gap_.clear();
        for (Eigen::Vector2i cell(ix + d.x(), iy + d.y()); inside(cell); cell += d) {
          if (!std::isinf(highest(cell.x(), cell.y()))) {
            // the ground beyond: a drop if its top lies far enough below the edge's foot (a
            // stone's top at the edge is no edge), less the fall of the ground before the edge,
            // and steeply enough on average that the hidden stretch is no hillside the sensor
            // looks over
            if (gap_.size() < 2) break;
            const double run_m = static_cast<double>(gap_.size() + 1) * step_m;
            const double drop_m = lowest(ix, iy) - highest(cell.x(), cell.y()) - fall() * run_m;
            if (drop_m > area.max_drop_m && drop_m > min_slope * run_m) {
              for (const Eigen::Vector2i& hidden : gap_) drops(hidden.x(), hidden.y()) = 1;
            }
            break;
          }
          // no gap reaches beyond the farthest the ground beyond may lie
          if (static_cast<double>(gap_.size() + 1) * step_m > area.drop_gap_m) {
            break;
          }
          gap_.push_back(cell);
        }
      }
    }
  }
  return drops_.const_view();
}

void ObstacleMarker::Mark(const WindowCrop& crop, const Eigen::Vector2i& low,
                          const Eigen::Vector2i& high, const MapArea& area,
                          const Eigen::Vector3d& p_WB, double t_s, int margin_cells,
                          common::GridLayers* map) {
  // the faces the height regression cannot see (their points were cropped as not terrain): the
  // latest observation of each cell decides, so a cell seen free again clears
  const common::GridGeometry& g = map->geometry();
  Eigen::MatrixXf& floor = map->Layer(layers::kFloor);
  const auto seen =
      Cells(crop.below_robot(), g, low, high, area.max_height_above_ground_m, area.max_step_m,
            area.max_bump_m, &crop, area.floor_steps ? &floor : nullptr);
  FaceHistory faces(map);
  Eigen::MatrixXf& rough = map->Layer(layers::kRoughness);
  const auto roughness = roughness_.const_view();
  Eigen::MatrixXf& out = map->Layer(layers::kTraversability);
  const Eigen::MatrixXf& scored_s = map->Layer(layers::kLastObserved);
  const auto lowest = lowest_.const_view();
  const auto highest = highest_.const_view();
  const auto extents = extents_.const_view();
  const int extents_width = high.x() - low.x() + 1;
  const double blind_radius2 = area.blind_radius_m * area.blind_radius_m;
  const auto drops = Drops(g, area, p_WB);
  for (int ix = low.x(); ix <= high.x(); ++ix) {
    for (int iy = low.y(); iy <= high.y(); ++iy) {
      const Eigen::Vector2i local(ix - low.x(), iy - low.y());
      float value = drops(local.x(), local.y()) != 0 ? 1.0f : seen(local.x(), local.y());
      // (fmin: a cell's first points set its floor)
      if (!std::isinf(lowest(local.x(), local.y()))) {
        floor(ix, iy) = std::fmin(floor(ix, iy), lowest(local.x(), local.y()));
      }
      // a step against the ground the cells showed before, though the frame shows none beside
      // the cell (StepAboveFloors)
      if (value == 0.0f && area.max_step_m > 0.0 && area.floor_steps &&
          StepAboveFloors(floor, ix, iy, highest(local.x(), local.y()),
                          crop.GroundGradient(g.CellCenter(ix, iy)), g.resolution_m,
                          area.max_step_m)) {
        value = 1.0f;
      }
      // a cell whose lowest point stands more than half the crop height above the lowest point it
      // ever showed shows no ground (the side of a box next to the robot, seen above the sensor's
      // lowest beam; the top of a low wall seen by a robot pitched up): it is no evidence of free
      // space, and a face if its top stands above the crop height
      const float above_ground = lowest(local.x(), local.y()) - floor(ix, iy);
      if (value == 0.0f && above_ground > 0.5 * area.max_height_above_ground_m) {
        value = highest(local.x(), local.y()) - floor(ix, iy) > area.max_height_above_ground_m
                    ? 1.0f
                    : kNaN;
      }
      if (!std::isnan(value)) {
        // a drop's face is the whole cell (no point shows it)
        faces.Observe(ix, iy, value, t_s, area,
                      drops(local.x(), local.y()) != 0
                          ? Eigen::Vector4f::Constant(kNaN)
                          : Eigen::Vector4f(extents.col(local.x() + extents_width * local.y())));
        rough(ix, iy) = roughness(local.x(), local.y());
      } else if (faces.Forgettable(ix, iy, t_s, area) && !std::isnan(rough(ix, iy)) &&
                 (g.CellCenter(ix, iy) - p_WB.head<2>()).squaredNorm() < blind_radius2) {
        // in the ground blind zone the cell is never seen free again: forget a short-lived face
        // (the legs of a walker pass a cell in well under a second; a wall the robot turns beside
        // showed its face from afar, and its cost without the face would be the ground's) but not
        // a drop, whose roughness its mark left unknown: the ground there may never be seen
        faces.Forget(ix, iy);
        if (std::isnan(scored_s(ix, iy))) out(ix, iy) = kNaN;
      }
    }
  }
  // closed by one cell: faces seen edge-on or occluded leave gaps of a cell or two in a wall,
  // never a passage. A cleared cell that the regression has never scored keeps its 1 (sparse
  // views of a real obstacle clear more often than movers do, and movers are kept out of the
  // frames). Only cells near the window can change: the closing there (the obstacle layer changed
  // in the window only) and the cost the mapper rewrote in the window and its margin; everywhere
  // else the previous frames already wrote the closed mask, so the result equals closing the whole
  // map.
  const int margin = margin_cells;
  const Eigen::Vector2i out_low = (low.array() - margin).max(0);
  const Eigen::Vector2i out_high =
      (high.array() + margin).min(Eigen::Array2i(g.num_x - 1, g.num_y - 1));
  // the closing of a cell reads the mask two cells around it
  const Eigen::Vector2i mask_low = (out_low.array() - 2).max(0);
  const Eigen::Vector2i mask_high =
      (out_high.array() + 2).min(Eigen::Array2i(g.num_x - 1, g.num_y - 1));
  const Eigen::Vector2i size = mask_high - mask_low + Eigen::Vector2i::Ones();
  mask_.Resize(size.x(), size.y()) =
      (faces.obstacle.block(mask_low.x(), mask_low.y(), size.x(), size.y()).array() == 1.0f)
          .cast<std::uint8_t>();
  CloseMask();
  const auto lethal = closed_.view();
  for (int ix = out_low.x(); ix <= out_high.x(); ++ix) {
    for (int iy = out_low.y(); iy <= out_high.y(); ++iy) {
      if (lethal(ix - mask_low.x(), iy - mask_low.y()) != 0) out(ix, iy) = 1.0f;
    }
  }
}

}  // namespace trav::mapping
