#include "mapping/baselines.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "common/stopwatch.h"
#include "mapping/fsgp_bgk_mapper.h"
#include "mapping/window.h"

namespace trav::mapping {
namespace {

constexpr int kMinimumPoints = 10;
// The obstacle layer's margin around the window: the closing reads two cells around a cell.
constexpr int kObstacleMargin = 2;

common::GridLayers MakeMap(const MapArea& area) {
  return common::GridLayers(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(),
                                     Eigen::Vector2d::Constant(area.map_size_m), area.resolution_m),
      layers::All());
}

// The window's points into `crop` (ground-cropped as `area` says, without the points that stand
// above their cells' floor in `map`), timed; a status of kTooFewPoints when there are fewer than
// the minimum.
void CropOrRefuse(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB,
                  const MapArea& area, const common::GridLayers& map, MapUpdateResult* result,
                  WindowCrop* crop) {
  const common::Stopwatch start;
  crop->Crop(points_W, p_WB, area.window_m, area.max_height_above_robot_m, area.GroundCropHeight(),
             result);
  crop->KeepNearFloor(map, area.GroundCropHeight());
  result->window_points = static_cast<int>(crop->window().cols());
  result->times.crop = start.ElapsedMilliseconds();
  if (crop->window().cols() < kMinimumPoints) result->status = MapUpdateStatus::kTooFewPoints;
}

}  // namespace

SgpMapper::SgpMapper(const SgpConfig& config) : config_(config), map_(MakeMap(config.area)) {}

MapUpdateResult SgpMapper::Update(const common::PointCloud& points_W, const Eigen::Isometry3d& X_WB,
                                  double t_s) {
  MapUpdateResult result;
  const Eigen::Vector3d p_WB = X_WB.translation();
  CropOrRefuse(points_W, p_WB, config_.area, map_, &result, &crop_);
  const auto window = crop_.window();
  if (result.status != MapUpdateStatus::kUpdated) return result;
  // inducing points on a stride of the points sorted by x
  common::Stopwatch stage;
  std::vector<Eigen::Index> order(static_cast<std::size_t>(window.cols()));
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<Eigen::Index>(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](Eigen::Index a, Eigen::Index b) { return window(0, a) < window(0, b); });
  const std::size_t stride =
      std::max<std::size_t>(1, order.size() / static_cast<std::size_t>(config_.inducing_points));
  std::vector<Eigen::Index> chosen;
  for (std::size_t i = 0; i < order.size(); i += stride) chosen.push_back(order[i]);
  const auto m = static_cast<Eigen::Index>(chosen.size());
  Eigen::MatrixXd inputs(m, 2);
  Eigen::VectorXd heights(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index i = chosen[static_cast<std::size_t>(k)];
    inputs.row(k) << window(0, i), window(1, i);
    heights[k] = window(2, i);
  }
  result.training_points = static_cast<int>(m);
  result.times.features = stage.ElapsedMilliseconds();
  stage.Restart();
  GpHyperparameters hyper;
  hyper.length_scales = Eigen::Vector4d::Constant(config_.length_scale_m);
  hyper.noise_std_m = config_.noise_std_m;
  if (!gp_.Fit(inputs, heights, hyper)) {
    result.status = MapUpdateStatus::kModelFailed;
    return result;
  }
  result.times.fit = stage.ElapsedMilliseconds();

  // predict every window cell near data
  stage.Restart();
  map_.Recenter(p_WB.head<2>());
  const common::GridGeometry& g = map_.geometry();
  const auto [low, high] = WindowCells(g, p_WB, config_.area.window_m);
  // the window's cells with an inducing point within the support radius: the cells FSGP-BGK
  // predicts (the same search, InverseDistanceWeighting's nearest training point)
  std::vector<Eigen::Vector2i> window_cells;
  Eigen::Matrix2Xd centres_W(2, (high - low + Eigen::Vector2i::Ones()).prod());
  for (int ix = low.x(); ix <= high.x(); ++ix) {
    for (int iy = low.y(); iy <= high.y(); ++iy) {
      centres_W.col(static_cast<Eigen::Index>(window_cells.size())) = g.CellCenter(ix, iy);
      window_cells.emplace_back(ix, iy);
    }
  }
  Eigen::Matrix3Xd inducing_W = Eigen::Matrix3Xd::Zero(3, m);
  inducing_W.topRows<2>() = inputs.transpose();
  support_.Compute(inducing_W, centres_W, 1, config_.support_radius_m);
  std::vector<Eigen::Vector2i> cells;
  for (std::size_t c = 0; c < window_cells.size(); ++c) {
    if (support_.nearest_m()[static_cast<Eigen::Index>(c)] <= config_.support_radius_m) {
      cells.push_back(window_cells[c]);
    }
  }
  Eigen::MatrixXd test(static_cast<Eigen::Index>(cells.size()), 2);
  for (std::size_t k = 0; k < cells.size(); ++k)
    test.row(static_cast<Eigen::Index>(k)) = g.CellCenter(cells[k].x(), cells[k].y()).transpose();
  Eigen::VectorXd f(test.rows()), variance(test.rows());
  Eigen::MatrixXd gradient(test.rows(), test.cols());
  // the cells' centres lie on the map's lattice
  gp_.PredictOnLattice(test, f, gradient);
  variance_.Compute(gp_, cells, test, low, high, config_.variance_stride, variance);
  Eigen::MatrixXf& elevation = map_.Layer(layers::kElevation);
  Eigen::MatrixXf& elevation_variance = map_.Layer(layers::kElevationVariance);
  Eigen::MatrixXf& slope_rad = map_.Layer(layers::kSlope);
  Eigen::MatrixXf& last_observed_s = map_.Layer(layers::kLastObserved);
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    elevation(cells[k].x(), cells[k].y()) = static_cast<float>(f[i]);
    elevation_variance(cells[k].x(), cells[k].y()) = static_cast<float>(variance[i]);
    slope_rad(cells[k].x(), cells[k].y()) = static_cast<float>(std::atan(gradient.row(i).norm()));
    last_observed_s(cells[k].x(), cells[k].y()) = static_cast<float>(t_s);
  }
  result.times.predict = stage.ElapsedMilliseconds();

  // step (max - min) and flatness (plane angle) over 5 x 5 cells, then the weighted score
  stage.Restart();
  ScoreCells(cells);
  if (config_.area.obstacle_layer) {
    obstacles_.Mark(crop_, low, high, config_.area, p_WB, t_s, kObstacleMargin, &map_);
  }
  result.observed_cells = static_cast<int>(cells.size());
  result.times.fusion = stage.ElapsedMilliseconds();
  return result;
}

void SgpMapper::ScoreCells(const std::vector<Eigen::Vector2i>& cells) {
  const common::GridGeometry& g = map_.geometry();
  const Eigen::MatrixXf& elevation = map_.Layer(layers::kElevation);
  const Eigen::MatrixXf& slope_rad = map_.Layer(layers::kSlope);
  Eigen::MatrixXf& gradient_m = map_.Layer(layers::kGradient);
  Eigen::MatrixXf& traversability = map_.Layer(layers::kTraversability);
  const int r = config_.score_window_cells / 2;
  for (const Eigen::Vector2i& c : cells) {
    double lowest = 1e9, highest = -1e9;
    std::vector<Eigen::Vector3d> around;
    for (int dx = -r; dx <= r; ++dx) {
      for (int dy = -r; dy <= r; ++dy) {
        if (!g.Contains(c.x() + dx, c.y() + dy)) continue;
        const float h = elevation(c.x() + dx, c.y() + dy);
        if (std::isnan(h)) continue;
        lowest = std::min(lowest, static_cast<double>(h));
        highest = std::max(highest, static_cast<double>(h));
        around.emplace_back(dx * g.resolution_m, dy * g.resolution_m, h);
      }
    }
    double flatness = 0.0;
    if (around.size() >= 3) {
      Eigen::MatrixXd design(static_cast<Eigen::Index>(around.size()), 3);
      Eigen::VectorXd z(static_cast<Eigen::Index>(around.size()));
      for (std::size_t k = 0; k < around.size(); ++k) {
        design.row(static_cast<Eigen::Index>(k)) << around[k].x(), around[k].y(), 1.0;
        z[static_cast<Eigen::Index>(k)] = around[k].z();
      }
      flatness = std::atan(design.colPivHouseholderQr().solve(z).head<2>().norm());
    }
    const double slope = slope_rad(c.x(), c.y());
    const double cost =
        config_.weight_step * std::min(1.0, (highest - lowest) / config_.step_critical_m) +
        config_.weight_flatness * std::min(1.0, flatness / config_.flatness_critical_rad) +
        config_.weight_slope * std::min(1.0, slope / config_.slope_critical_rad);
    gradient_m(c.x(), c.y()) = static_cast<float>(highest - lowest);
    traversability(c.x(), c.y()) = static_cast<float>(std::clamp(cost, 0.0, 1.0));
  }
}

ElevationMapper::ElevationMapper(const ElevationMapConfig& config, const FsgpConfig& score)
    : config_(config), score_(score), map_(MakeMap(config.area)) {}

MapUpdateResult ElevationMapper::Update(const common::PointCloud& points_W,
                                        const Eigen::Isometry3d& X_WB, double t_s) {
  MapUpdateResult result;
  const Eigen::Vector3d p_WB = X_WB.translation();
  CropOrRefuse(points_W, p_WB, config_.area, map_, &result, &crop_);
  const auto window = crop_.window();
  if (result.status != MapUpdateStatus::kUpdated) return result;
  // per-cell Kalman fusion of the point heights
  common::Stopwatch stage;
  map_.Recenter(p_WB.head<2>());
  const common::GridGeometry& g = map_.geometry();
  Eigen::MatrixXf& h = map_.Layer(layers::kElevation);
  Eigen::MatrixXf& v = map_.Layer(layers::kElevationVariance);
  Eigen::MatrixXf& last = map_.Layer(layers::kLastObserved);
  for (Eigen::Index i = 0; i < window.cols(); ++i) {
    const Eigen::Vector3f p = window.col(i);
    const std::optional<Eigen::Vector2i> cell = g.CellIndex(p.head<2>().cast<double>());
    if (!cell) continue;
    const double d = (p.cast<double>() - p_WB).norm();
    const double sigma = config_.range_noise_m + config_.range_noise_growth * d * d;
    float& height = h(cell->x(), cell->y());
    float& variance = v(cell->x(), cell->y());
    if (std::isnan(height) ||
        p.z() - height > config_.mahalanobis_threshold * std::sqrt(variance + sigma * sigma)) {
      height = p.z();
      variance = static_cast<float>(sigma * sigma);
    } else {
      const double s2 = sigma * sigma;
      height = static_cast<float>((variance * p.z() + s2 * height) / (variance + s2));
      variance = static_cast<float>(variance * s2 / (variance + s2));
    }
    last(cell->x(), cell->y()) = static_cast<float>(t_s);
  }
  result.times.fusion = stage.ElapsedMilliseconds();

  // the score's terms on the fused elevation around every known window cell
  stage.Restart();
  const auto [low, high] = WindowCells(g, p_WB, config_.area.window_m);
  const int r =
      static_cast<int>(std::floor(config_.neighbourhood_radius_m / g.resolution_m + 1e-9));
  std::vector<Eigen::Vector3d> around;
  Eigen::MatrixXf& slope_rad = map_.Layer(layers::kSlope);
  Eigen::MatrixXf& curvature_layer = map_.Layer(layers::kCurvature);
  Eigen::MatrixXf& gradient_m = map_.Layer(layers::kGradient);
  Eigen::MatrixXf& traversability = map_.Layer(layers::kTraversability);
  for (int ix = low.x(); ix <= high.x(); ++ix) {
    for (int iy = low.y(); iy <= high.y(); ++iy) {
      if (std::isnan(h(ix, iy))) continue;
      around.clear();
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      double gradient = 0.0;
      for (int dx = -r; dx <= r; ++dx) {
        for (int dy = -r; dy <= r; ++dy) {
          if (!g.Contains(ix + dx, iy + dy) || std::isnan(h(ix + dx, iy + dy))) continue;
          if ((dx * dx + dy * dy) * g.resolution_m * g.resolution_m >
              config_.neighbourhood_radius_m * config_.neighbourhood_radius_m + 1e-9)
            continue;
          const Eigen::Vector3d q(dx * g.resolution_m, dy * g.resolution_m, h(ix + dx, iy + dy));
          around.push_back(q);
          mean += q;
          gradient += std::abs(q.z() - h(ix, iy));
        }
      }
      if (around.size() < 3) continue;
      const double n = static_cast<double>(around.size());
      mean /= n;
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      Eigen::MatrixXd design(static_cast<Eigen::Index>(around.size()), 3);
      Eigen::VectorXd z(static_cast<Eigen::Index>(around.size()));
      for (std::size_t k = 0; k < around.size(); ++k) {
        covariance += (around[k] - mean) * (around[k] - mean).transpose();
        design.row(static_cast<Eigen::Index>(k)) << around[k].x(), around[k].y(), 1.0;
        z[static_cast<Eigen::Index>(k)] = around[k].z();
      }
      covariance /= n - 1.0;
      const Eigen::Vector3d eigenvalues =
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly)
              .eigenvalues();
      const double curvature = std::max(0.0, eigenvalues[0]) / (eigenvalues.sum() + 1e-6);
      const double slope = std::atan(design.colPivHouseholderQr().solve(z).head<2>().norm());
      gradient /= n;
      slope_rad(ix, iy) = static_cast<float>(slope);
      curvature_layer(ix, iy) = static_cast<float>(curvature);
      gradient_m(ix, iy) = static_cast<float>(gradient);
      traversability(ix, iy) =
          static_cast<float>(PreliminaryScore(score_, curvature, gradient, slope));
      ++result.observed_cells;
    }
  }
  if (config_.area.obstacle_layer) {
    obstacles_.Mark(crop_, low, high, config_.area, p_WB, t_s, kObstacleMargin, &map_);
  }
  result.times.smoothing = stage.ElapsedMilliseconds();
  return result;
}

}  // namespace trav::mapping
