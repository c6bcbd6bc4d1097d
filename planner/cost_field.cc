#include "planner/cost_field.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace trav::planner {
namespace {

using Mask = Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>;

// True if the obstacle of lethal cell (ix, iy) is the whole cell: `extents` are empty or unknown
// (NaN) there.
bool WholeCell(const CellExtents& extents, int ix, int iy) {
  return extents.empty() || std::isnan(extents.x_low(ix, iy)) ||
         std::isnan(extents.x_high(ix, iy)) || std::isnan(extents.y_low(ix, iy)) ||
         std::isnan(extents.y_high(ix, iy));
}

// The obstacle within lethal cell (ix, iy) of `g`: the box `extents` gives (clamped to the cell),
// or the whole cell.
Eigen::AlignedBox2d ObstacleBox(const common::GridGeometry& g, const CellExtents& extents, int ix,
                                int iy) {
  const Eigen::Vector2d centre = g.CellCenter(ix, iy);
  const double half = 0.5 * g.resolution_m;
  if (WholeCell(extents, ix, iy)) {
    return Eigen::AlignedBox2d(centre.array() - half, centre.array() + half);
  }
  auto offset = [&](float v) { return std::clamp(static_cast<double>(v), -half, half); };
  return Eigen::AlignedBox2d(
      centre + Eigen::Vector2d(offset(extents.x_low(ix, iy)), offset(extents.y_low(ix, iy))),
      centre + Eigen::Vector2d(offset(extents.x_high(ix, iy)), offset(extents.y_high(ix, iy))));
}

// Squared-distance transform of one line: d(q) = min_p (q - p)^2 + f(p), by the lower envelope of
// the parabolas rooted at each p. `f` uses a large finite value for "no site" so that the
// intersection arithmetic stays finite.
void Transform1d(const std::vector<double>& f, std::vector<double>* d, std::vector<int>* v,
                 std::vector<double>* z) {
  const int n = static_cast<int>(f.size());
  int k = 0;
  (*v)[0] = 0;
  (*z)[0] = -std::numeric_limits<double>::infinity();
  (*z)[1] = std::numeric_limits<double>::infinity();
  auto intersection = [&](int q, int p) {
    return ((f[q] + static_cast<double>(q) * q) - (f[p] + static_cast<double>(p) * p)) /
           (2.0 * q - 2.0 * p);
  };
  for (int q = 1; q < n; ++q) {
    double s = intersection(q, (*v)[k]);
    while (s <= (*z)[k]) {
      --k;
      s = intersection(q, (*v)[k]);
    }
    ++k;
    (*v)[k] = q;
    (*z)[k] = s;
    (*z)[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while ((*z)[k + 1] < q) ++k;
    const double dq = q - (*v)[k];
    (*d)[q] = dq * dq + f[(*v)[k]];
  }
}

// Sweeps of GroundElevation's smoothing: on a fill 1 m wide at 0.1 m cells they bring the slope to
// within 0.05 of a plane's (CostFieldTest); a fixed count, so the result never depends on
// convergence tests or time.
constexpr int kSmoothingSweeps = 60;

// The ground's height for the slope limits: `elevation_m` where the cell lies at least `reach_m`
// from lethal cells (`distance_m`); nearer, where the mapped elevation is the regression's ramp
// up an obstacle's foot (its lowest points are taken for ground), the height of the nearest cell
// that far out, in steps between 8-connected cells (breadth first, in cell order: deterministic);
// NaN where the map has none or no such cell is connected. Reading the ramp as a slope made the
// tilt penalty push trajectories round every trunk and box, and fading the penalty out near them
// instead pulled trajectories toward them (the penalty falls with the distance): both are gone.
Eigen::MatrixXd GroundElevation(const Eigen::MatrixXf& elevation_m,
                                const Eigen::MatrixXd& distance_m, double reach_m) {
  const auto nx = static_cast<int>(elevation_m.rows()), ny = static_cast<int>(elevation_m.cols());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd ground = Eigen::MatrixXd::Constant(nx, ny, nan);
  std::deque<std::pair<int, int>> frontier;
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      if (distance_m(ix, iy) >= reach_m && std::isfinite(elevation_m(ix, iy))) {
        ground(ix, iy) = elevation_m(ix, iy);
        frontier.emplace_back(ix, iy);
      }
    }
  }
  std::vector<std::pair<int, int>> filled;
  while (!frontier.empty()) {
    const auto [x, y] = frontier.front();
    frontier.pop_front();
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int ix = x + dx, iy = y + dy;
        if (ix < 0 || iy < 0 || ix >= nx || iy >= ny || !std::isnan(ground(ix, iy)) ||
            !std::isfinite(elevation_m(ix, iy))) {
          continue;
        }
        ground(ix, iy) = ground(x, y);
        frontier.emplace_back(ix, iy);
        filled.emplace_back(ix, iy);
      }
    }
  }
  // the copies meet in seams; Gauss-Seidel sweeps of Laplace's equation over the filled cells
  // (each the mean of its known 4-neighbours, the cells beyond the reach fixed) smooth them toward
  // the harmonic fill, which on planar ground is the plane itself
  for (int sweep = 0; sweep < kSmoothingSweeps; ++sweep) {
    for (const auto& [x, y] : filled) {
      double sum = 0.0;
      int count = 0;
      for (const auto& [ix, iy] :
           {std::pair(x - 1, y), std::pair(x + 1, y), std::pair(x, y - 1), std::pair(x, y + 1)}) {
        if (ix < 0 || iy < 0 || ix >= nx || iy >= ny || std::isnan(ground(ix, iy))) continue;
        sum += ground(ix, iy);
        ++count;
      }
      // a cell reached only diagonally may have no known 4-neighbour: it keeps its copy
      if (count > 0) ground(x, y) = sum / count;
    }
  }
  return ground;
}

}  // namespace

Eigen::MatrixXd MinimumWithinDisc(const Eigen::MatrixXd& values, int radius) {
  if (radius <= 0) return values;
  const auto nx = static_cast<int>(values.rows()), ny = static_cast<int>(values.cols());
  // the disc's half-width along x at each row offset dy: the largest w with w^2 + dy^2 <= r^2
  std::vector<int> half_width(static_cast<std::size_t>(radius) + 1);
  for (int dy = 0; dy <= radius; ++dy) {
    int w = radius;
    while (w * w + dy * dy > radius * radius) --w;
    half_width[static_cast<std::size_t>(dy)] = w;
  }
  // the minimum along x over each half-width the disc has, then over the rows; a width's minimum
  // is the next narrower one's with the two cells it adds (an exact minimum, in any order)
  std::vector<Eigen::MatrixXd> along_x(static_cast<std::size_t>(radius) + 1);
  Eigen::MatrixXd widening = values;
  for (int w = 1; w <= radius; ++w) {
    for (int iy = 0; iy < ny; ++iy) {
      for (int ix = 0; ix < nx; ++ix) {
        if (ix - w >= 0) widening(ix, iy) = std::min(widening(ix, iy), values(ix - w, iy));
        if (ix + w < nx) widening(ix, iy) = std::min(widening(ix, iy), values(ix + w, iy));
      }
    }
    if (std::find(half_width.begin(), half_width.end(), w) != half_width.end()) {
      along_x[static_cast<std::size_t>(w)] = widening;
    }
  }
  along_x[0] = values;
  Eigen::MatrixXd eroded = along_x[static_cast<std::size_t>(radius)];
  for (int iy = 0; iy < ny; ++iy) {
    for (int dy = 1; dy <= radius; ++dy) {
      const Eigen::MatrixXd& row_min =
          along_x[static_cast<std::size_t>(half_width[static_cast<std::size_t>(dy)])];
      if (iy - dy >= 0) eroded.col(iy) = eroded.col(iy).cwiseMin(row_min.col(iy - dy));
      if (iy + dy < ny) eroded.col(iy) = eroded.col(iy).cwiseMin(row_min.col(iy + dy));
    }
  }
  return eroded;
}

namespace {

// The terrain's speed limit per cell (CostField::SpeedLimit).
Eigen::MatrixXd SpeedLimits(const Eigen::MatrixXf& cost, const Eigen::MatrixXf* roughness_m,
                            const TerrainSpeedConfig& config, double resolution_m) {
  Eigen::MatrixXd limit(cost.rows(), cost.cols());
  for (int iy = 0; iy < cost.cols(); ++iy) {
    for (int ix = 0; ix < cost.rows(); ++ix) {
      if (std::isnan(cost(ix, iy))) {
        limit(ix, iy) = std::min(config.open_m_s, config.unknown_m_s);
      } else {
        const float roughness = roughness_m != nullptr ? (*roughness_m)(ix, iy) : 0.0f;
        limit(ix, iy) = config.ForRoughness(std::isnan(roughness) ? 0.0 : roughness);
      }
    }
  }
  return MinimumWithinDisc(limit,
                           static_cast<int>(std::ceil(config.reach_m / resolution_m - 1e-9)));
}

// The structure tensor's half-width round a step cell [m]: wider than the ridge that a step's
// edge draws in the roughness (two cells), so that both its flanks count.
constexpr double kStepWindow_m = 0.5;
// The structure tensor's coherence from which a step cell's direction counts, and from which in
// full: straight edges at any angle read at least 0.77 on a grid (CostFieldTest: weights above
// 0.85), a 0.4 m square bump below 0.6.
constexpr double kCoherentFrom = 0.6;
constexpr double kCoherentAt = 0.8;

// The step fields of CostField::StepWeight and StepAxis: (weight, w cos 2 phi, w sin 2 phi), from
// the roughness and the cells that IsLethal reads lethal.
std::array<Eigen::MatrixXd, 3> StepFields(const Eigen::MatrixXf& cost,
                                          const Eigen::MatrixXf* roughness_m, const Mask& lethal,
                                          const StepCrossing& steps, double resolution_m) {
  const auto nx = static_cast<int>(cost.rows()), ny = static_cast<int>(cost.cols());
  std::array<Eigen::MatrixXd, 3> fields{
      Eigen::MatrixXd::Zero(nx, ny), Eigen::MatrixXd::Zero(nx, ny), Eigen::MatrixXd::Zero(nx, ny)};
  // most maps hold no step: then nothing more is needed
  if (roughness_m == nullptr || !steps.Active() ||
      !roughness_m->unaryExpr([&](float r) { return steps.Weight(r) > 0.0; }).any()) {
    return fields;
  }
  // the roughness of a cell beside a lethal one measures the obstacle (its top enters the second
  // differences), not a step: 0 there, as where it is unknown, so that no wall reads as a step
  // to cross at right angles
  Eigen::MatrixXd rough(nx, ny);
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      const float r = (*roughness_m)(ix, iy);
      const int x0 = std::max(0, ix - 1), y0 = std::max(0, iy - 1);
      const bool beside_lethal =
          lethal.block(x0, y0, std::min(nx - 1, ix + 1) - x0 + 1, std::min(ny - 1, iy + 1) - y0 + 1)
              .any();
      rough(ix, iy) = std::isnan(r) || beside_lethal ? 0.0 : r;
    }
  }
  // the roughness's gradient by Scharr's operator (the border cells replicated beyond the grid):
  // of the 3 x 3 derivative filters the one whose direction errs least on a grid (Jaehne, Scharr
  // and Koerkel, "Principles of filter design", 1999); plain central differences read an edge at
  // 30 deg from the grid at 36 deg
  auto at = [&](int ix, int iy) {
    return rough(std::clamp(ix, 0, nx - 1), std::clamp(iy, 0, ny - 1));
  };
  Eigen::MatrixXd gx(nx, ny), gy(nx, ny);
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      gx(ix, iy) = (3.0 * (at(ix + 1, iy - 1) - at(ix - 1, iy - 1)) +
                    10.0 * (at(ix + 1, iy) - at(ix - 1, iy)) +
                    3.0 * (at(ix + 1, iy + 1) - at(ix - 1, iy + 1))) /
                   32.0;
      gy(ix, iy) = (3.0 * (at(ix - 1, iy + 1) - at(ix - 1, iy - 1)) +
                    10.0 * (at(ix, iy + 1) - at(ix, iy - 1)) +
                    3.0 * (at(ix + 1, iy + 1) - at(ix + 1, iy - 1))) /
                   32.0;
    }
  }
  const int window_cells = std::max(1, static_cast<int>(std::lround(kStepWindow_m / resolution_m)));
  const int reach_cells = static_cast<int>(std::ceil(steps.reach_m / resolution_m - 1e-9));
  auto& [weight, axis_x, axis_y] = fields;
  // the squared distance [cells^2] to the step cell each cell took its weight from: of equal
  // weights (every full-height step's) the nearest step's direction holds
  Eigen::MatrixXi from = Eigen::MatrixXi::Constant(nx, ny, std::numeric_limits<int>::max());
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      if (std::isnan(cost(ix, iy))) continue;
      const double strength = steps.Weight(rough(ix, iy));
      if (strength <= 0.0) continue;
      // the structure tensor J = sum g g^T over the window; its dominant eigenvector is the
      // normal of the ridge, at the doubled angle of (Jxx - Jyy, 2 Jxy), and its coherence
      // |(Jxx - Jyy, 2 Jxy)| / (Jxx + Jyy) is 1 along a straight edge and 0 at a corner
      double jxx = 0.0, jyy = 0.0, jxy = 0.0;
      for (int jy = std::max(0, iy - window_cells); jy <= std::min(ny - 1, iy + window_cells);
           ++jy) {
        for (int jx = std::max(0, ix - window_cells); jx <= std::min(nx - 1, ix + window_cells);
             ++jx) {
          jxx += gx(jx, jy) * gx(jx, jy);
          jyy += gy(jx, jy) * gy(jx, jy);
          jxy += gx(jx, jy) * gy(jx, jy);
        }
      }
      const Eigen::Vector2d doubled(jxx - jyy, 2.0 * jxy);
      const double norm = doubled.norm();
      if (!(norm > 0.0)) continue;
      // a bump or a corner is no edge to cross square: the weight fades with the coherence
      const double coherence = norm / (jxx + jyy);
      const double w =
          strength *
          std::clamp((coherence - kCoherentFrom) / (kCoherentAt - kCoherentFrom), 0.0, 1.0);
      if (!(w > 0.0)) continue;
      const Eigen::Vector2d axis = w / norm * doubled;
      for (int dy = -reach_cells; dy <= reach_cells; ++dy) {
        for (int dx = -reach_cells; dx <= reach_cells; ++dx) {
          const int jx = ix + dx, jy = iy + dy, squared = dx * dx + dy * dy;
          if (squared > reach_cells * reach_cells || jx < 0 || jy < 0 || jx >= nx || jy >= ny ||
              w < weight(jx, jy) || (w == weight(jx, jy) && squared >= from(jx, jy))) {
            continue;
          }
          weight(jx, jy) = w;
          from(jx, jy) = squared;
          axis_x(jx, jy) = axis.x();
          axis_y(jx, jy) = axis.y();
        }
      }
    }
  }
  return fields;
}

}  // namespace

Eigen::MatrixXd DistanceTransform(const Mask& mask) {
  constexpr double kNoSite = 1e20;
  const int nx = static_cast<int>(mask.rows()), ny = static_cast<int>(mask.cols());
  Eigen::MatrixXd squared(nx, ny);
  const int longest = std::max(nx, ny);
  std::vector<double> f(longest), d(longest), z(longest + 1);
  std::vector<int> v(longest);
  // along y for each x, then along x for each y
  f.resize(ny);
  d.resize(ny);
  for (int ix = 0; ix < nx; ++ix) {
    for (int iy = 0; iy < ny; ++iy) f[iy] = mask(ix, iy) ? 0.0 : kNoSite;
    Transform1d(f, &d, &v, &z);
    for (int iy = 0; iy < ny; ++iy) squared(ix, iy) = d[iy];
  }
  f.resize(nx);
  d.resize(nx);
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) f[ix] = squared(ix, iy);
    Transform1d(f, &d, &v, &z);
    for (int ix = 0; ix < nx; ++ix) squared(ix, iy) = d[ix];
  }
  return squared.unaryExpr([&](double s) {
    return s >= 0.5 * kNoSite ? std::numeric_limits<double>::infinity() : std::sqrt(s);
  });
}

Eigen::MatrixXd ObstacleDistance(const common::GridGeometry& g, const Mask& lethal,
                                 const CellExtents& extents) {
  const int nx = g.num_x, ny = g.num_y;
  const Eigen::MatrixXd centre_cells = DistanceTransform(lethal);
  Eigen::MatrixXd distance_m(nx, ny);
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      distance_m(ix, iy) = lethal(ix, iy) ? 0.0 : (centre_cells(ix, iy) - 0.5) * g.resolution_m;
    }
  }
  if (extents.empty()) return distance_m;
  auto whole = [&](int ix, int iy) { return WholeCell(extents, ix, iy); };
  // a whole lethal cell whose four side neighbours are whole lethal cells is never the nearest
  // obstacle: its boundary is theirs
  auto hidden = [&](int ix, int iy) {
    if (!whole(ix, iy) || ix == 0 || iy == 0 || ix == nx - 1 || iy == ny - 1) return false;
    const std::array<Eigen::Vector2i, 4> sides{
        {{ix - 1, iy}, {ix + 1, iy}, {ix, iy - 1}, {ix, iy + 1}}};
    return std::all_of(sides.begin(), sides.end(), [&](const Eigen::Vector2i& n) {
      return lethal(n.x(), n.y()) && whole(n.x(), n.y());
    });
  };
  // the cells that take the exact distance: within the reach, and not inside a whole lethal cell
  // (which holds its centre: 0)
  Mask target(nx, ny);
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      target(ix, iy) = lethal(ix, iy) ? !whole(ix, iy) : distance_m(ix, iy) < kExactReach_m;
    }
  }
  // the nearest obstacle of a cell within the reach lies within the reach, plus the half-diagonal
  // of its cell, of the cell's centre, which lies within the reach plus half a cell of the nearest
  // lethal centre, whose obstacle may lie a half-diagonal beyond it
  const int window = static_cast<int>(std::ceil(kExactReach_m / g.resolution_m + 2.0));
  // The squared distance from a box to a cell centre is the sum of its squares along x and y,
  // each taken once per window column and row (what Eigen::AlignedBox2d::squaredExteriorDistance
  // sums, in the same order, so the distances are the same to the bit).
  auto squared_outside = [](double p, double low, double high) {
    const double outside = p < low ? low - p : (p > high ? p - high : 0.0);
    return outside * outside;
  };
  std::vector<double> centre_x(nx), centre_y(ny);
  for (int jx = 0; jx < nx; ++jx) centre_x[jx] = g.CellCenter(jx, 0).x();
  for (int jy = 0; jy < ny; ++jy) centre_y[jy] = g.CellCenter(0, jy).y();
  std::vector<double> squared_x(2 * window + 1), squared_y(2 * window + 1);
  Eigen::MatrixXd squared =
      Eigen::MatrixXd::Constant(nx, ny, std::numeric_limits<double>::infinity());
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      if (!lethal(ix, iy) || hidden(ix, iy)) continue;
      const Eigen::AlignedBox2d box = ObstacleBox(g, extents, ix, iy);
      const int x0 = std::max(0, ix - window), x1 = std::min(nx - 1, ix + window);
      const int y0 = std::max(0, iy - window), y1 = std::min(ny - 1, iy + window);
      for (int jx = x0; jx <= x1; ++jx) {
        squared_x[jx - x0] = squared_outside(centre_x[jx], box.min().x(), box.max().x());
      }
      for (int jy = y0; jy <= y1; ++jy) {
        squared_y[jy - y0] = squared_outside(centre_y[jy], box.min().y(), box.max().y());
      }
      // every cell of the window, without a branch (the loop vectorises); only targets are read
      for (int jy = y0; jy <= y1; ++jy) {
        double* column = &squared(0, jy);
        const double along_y = squared_y[jy - y0];
        for (int jx = x0; jx <= x1; ++jx) {
          column[jx] = std::min(column[jx], squared_x[jx - x0] + along_y);
        }
      }
    }
  }
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      if (target(ix, iy) && std::isfinite(squared(ix, iy))) {
        distance_m(ix, iy) = std::sqrt(squared(ix, iy));
      }
    }
  }
  return distance_m;
}

Eigen::MatrixXd LethalDistance(const common::GridGeometry& g, const Eigen::MatrixXf& layer,
                               const CostMapConfig& config, const CellExtents& extents,
                               bool known_only) {
  const Mask lethal = layer.unaryExpr(
      [&](float c) { return IsLethal(c, config) && !(known_only && std::isnan(c)); });
  return ObstacleDistance(g, lethal, extents);
}

CostField::CostField(const common::GridLayers& map, const CostMapConfig& config)
    : CostField(map.geometry(), map.Layer(config.cost_layer), config,
                map.Has(config.speed.roughness_layer) ? &map.Layer(config.speed.roughness_layer)
                                                      : nullptr,
                map.Has(config.slope.elevation_layer) ? &map.Layer(config.slope.elevation_layer)
                                                      : nullptr,
                CellExtents::Of(map, config)) {}

CostField::CostField(const common::GridGeometry& geometry, const Eigen::MatrixXf& layer,
                     const CostMapConfig& config, const Eigen::MatrixXf* roughness_m,
                     const Eigen::MatrixXf* elevation_m, const CellExtents& extents)
    : CostField(geometry, layer, config, roughness_m, elevation_m,
                LethalDistance(geometry, layer, config, extents, /*known_only=*/false), extents) {}

CostField::CostField(const common::GridGeometry& geometry, const Eigen::MatrixXf& layer,
                     const CostMapConfig& config, const Eigen::MatrixXf* roughness_m,
                     const Eigen::MatrixXf* elevation_m, const Eigen::MatrixXd& outside_m,
                     const CellExtents& extents)
    : geometry_(geometry),
      max_pitch_roll_tangents_(config.slope.Tangents()),
      open_speed_m_s_(config.speed.open_m_s),
      step_cos_twice_max_angle_(std::cos(2.0 * config.steps.max_angle_deg * M_PI / 180.0)) {
  const int nx = geometry_.num_x, ny = geometry_.num_y;
  cost_.resize(nx, ny);
  Mask lethal(nx, ny);
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      const float c = layer(ix, iy);
      cost_(ix, iy) =
          std::isnan(c) ? config.unknown_cost : std::clamp(static_cast<double>(c), 0.0, 1.0);
      lethal(ix, iy) = IsLethal(c, config);
    }
  }
  // signed distance: outside, to the obstacles (between cell boundaries where their extents are
  // unknown); inside, half a cell less than between centres, so that it crosses zero on the
  // boundary of the lethal region
  const Eigen::MatrixXd inside = DistanceTransform(lethal.unaryExpr([](bool b) { return !b; }));
  distance_.resize(nx, ny);
  const double half = 0.5;
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      double d = 0.0;
      if (!lethal(ix, iy) || outside_m(ix, iy) > 0.0) {
        d = std::isfinite(outside_m(ix, iy)) ? outside_m(ix, iy) : kFarDistance;
      } else {
        d = std::isfinite(inside(ix, iy)) ? -(inside(ix, iy) - half) * geometry_.resolution_m
                                          : -kFarDistance;
      }
      distance_(ix, iy) = d;
    }
  }
  FindNearestObstacles(lethal, extents);
  speed_limit_ = SpeedLimits(layer, roughness_m, config.speed, geometry_.resolution_m);
  auto steps = StepFields(layer, roughness_m, lethal, config.steps, geometry_.resolution_m);
  step_weight_ = std::move(steps[0]);
  step_axis_x_ = std::move(steps[1]);
  step_axis_y_ = std::move(steps[2]);
  has_steps_ = (step_weight_.array() > 0.0).any();
  elevation_ = elevation_m != nullptr && config.slope.Active()
                   ? GroundElevation(*elevation_m, distance_, kGroundReach_m)
                   : Eigen::MatrixXd::Constant(nx, ny, std::numeric_limits<double>::quiet_NaN());
}

std::vector<Eigen::Vector2d> BodyPoints_B(const common::Footprint& footprint, double resolution_m,
                                          double clearance_m) {
  return footprint.BoundaryPoints_B(
      std::min(resolution_m, std::max(0.5 * clearance_m, 0.25 * resolution_m)));
}

void CostField::FindNearestObstacles(const Mask& lethal, const CellExtents& extents) {
  const common::GridGeometry& g = geometry_;
  nearest_obstacle_ = Eigen::MatrixXi::Constant(g.num_x, g.num_y, -1);
  obstacles_.clear();
  // each lethal cell's index in obstacles_, once it is some centre's candidate
  Eigen::MatrixXi index = Eigen::MatrixXi::Constant(g.num_x, g.num_y, -1);
  // the obstacle nearest to a centre within the band lies within the band of it, its cell's
  // centre within half a diagonal more
  const int window =
      static_cast<int>(std::ceil((kExactBand_m + M_SQRT1_2 * g.resolution_m) / g.resolution_m));
  auto obstacle_of = [&](int jx, int jy) {
    if (index(jx, jy) < 0) {
      index(jx, jy) = static_cast<int>(obstacles_.size());
      obstacles_.push_back(ObstacleBox(g, extents, jx, jy));
    }
    return index(jx, jy);
  };
  for (int iy = 0; iy < g.num_y; ++iy) {
    for (int ix = 0; ix < g.num_x; ++ix) {
      if (!(distance_(ix, iy) <= kExactBand_m)) continue;
      // a face's cell whose box holds its centre (a distance of 0 or less) is its own nearest
      if (lethal(ix, iy) && distance_(ix, iy) <= 0.0) {
        if (!WholeCell(extents, ix, iy)) nearest_obstacle_(ix, iy) = obstacle_of(ix, iy);
        continue;
      }
      const Eigen::Vector2d centre = g.CellCenter(ix, iy);
      double best = std::numeric_limits<double>::infinity();
      for (int jy = std::max(0, iy - window); jy <= std::min(g.num_y - 1, iy + window); ++jy) {
        for (int jx = std::max(0, ix - window); jx <= std::min(g.num_x - 1, ix + window); ++jx) {
          if (!lethal(jx, jy) || WholeCell(extents, jx, jy)) continue;
          const int k = obstacle_of(jx, jy);
          const double squared =
              obstacles_[static_cast<std::size_t>(k)].squaredExteriorDistance(centre);
          if (squared < best) {
            best = squared;
            nearest_obstacle_(ix, iy) = k;
          }
        }
      }
    }
  }
}

FieldSample CostField::Distance(const Eigen::Vector2d& p_W) const {
  const FieldSample interpolated = Interpolate(distance_, p_W);
  const common::GridGeometry& g = geometry_;
  const Eigen::Vector2d cell = (p_W - g.origin_W) / g.resolution_m;
  if (obstacles_.empty() ||
      !(cell.x() >= 0.0 && cell.x() <= g.num_x - 1 && cell.y() >= 0.0 && cell.y() <= g.num_y - 1)) {
    return interpolated;
  }
  // the obstacles nearest to the four centres around p_W, as Interpolate takes them
  const int x0 = std::max(0, std::min(static_cast<int>(cell.x()), g.num_x - 2));
  const int y0 = std::max(0, std::min(static_cast<int>(cell.y()), g.num_y - 2));
  const int x1 = std::min(x0 + 1, g.num_x - 1), y1 = std::min(y0 + 1, g.num_y - 1);
  double best = std::numeric_limits<double>::infinity();
  const Eigen::AlignedBox2d* nearest = nullptr;
  for (const auto& [jx, jy] : {std::pair{x0, y0}, {x1, y0}, {x0, y1}, {x1, y1}}) {
    const int k = nearest_obstacle_(jx, jy);
    // a centre off the band: the interpolation alone
    if (k < 0) return interpolated;
    const double squared = obstacles_[static_cast<std::size_t>(k)].squaredExteriorDistance(p_W);
    if (squared < best) {
      best = squared;
      nearest = &obstacles_[static_cast<std::size_t>(k)];
    }
  }
  // inside an obstacle: no farther than its boundary
  if (best == 0.0) {
    FieldSample inside = interpolated;
    inside.value = std::min(inside.value, 0.0);
    return inside;
  }
  const double exact = std::sqrt(best);
  if (exact >= interpolated.value) return interpolated;
  FieldSample sample;
  sample.value = exact;
  sample.gradient_W = (p_W - p_W.cwiseMax(nearest->min()).cwiseMin(nearest->max())) / exact;
  return sample;
}

double FootprintDistance(const CostField& field, const Eigen::Vector2d& position_W, double yaw,
                         const std::vector<Eigen::Vector2d>& body_points_B) {
  const Eigen::Rotation2Dd R_WB(yaw);
  double smallest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& b : body_points_B) {
    smallest = std::min(smallest, field.Distance(position_W + R_WB * b).value);
  }
  return smallest;
}

FieldSample CostField::Interpolate(const Eigen::MatrixXd& layer, const Eigen::Vector2d& p_W) const {
  const common::GridGeometry& g = geometry_;
  const Eigen::Vector2d cell = (p_W - g.origin_W) / g.resolution_m;
  const double fx = std::clamp(cell.x(), 0.0, static_cast<double>(g.num_x - 1));
  const double fy = std::clamp(cell.y(), 0.0, static_cast<double>(g.num_y - 1));
  const int x0 = std::max(0, std::min(static_cast<int>(fx), g.num_x - 2));
  const int y0 = std::max(0, std::min(static_cast<int>(fy), g.num_y - 2));
  const int x1 = std::min(x0 + 1, g.num_x - 1), y1 = std::min(y0 + 1, g.num_y - 1);
  const double tx = fx - x0, ty = fy - y0;
  const double v00 = layer(x0, y0), v10 = layer(x1, y0), v01 = layer(x0, y1), v11 = layer(x1, y1);
  FieldSample sample;
  sample.value = (1 - ty) * ((1 - tx) * v00 + tx * v10) + ty * ((1 - tx) * v01 + tx * v11);
  // clamped coordinates do not move with p_W: zero gradient along them
  const bool inside_x = cell.x() > 0.0 && cell.x() < g.num_x - 1;
  const bool inside_y = cell.y() > 0.0 && cell.y() < g.num_y - 1;
  if (inside_x) {
    sample.gradient_W.x() = ((1 - ty) * (v10 - v00) + ty * (v11 - v01)) / g.resolution_m;
  }
  if (inside_y) {
    sample.gradient_W.y() = ((1 - tx) * (v01 - v00) + tx * (v11 - v10)) / g.resolution_m;
  }
  if (inside_x && inside_y) {
    sample.cross_derivative = (v11 - v01 - v10 + v00) / (g.resolution_m * g.resolution_m);
  }
  return sample;
}

}  // namespace trav::planner
