#include "mapping/fsgp_bgk_mapper.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "mapping/features.h"
#include "mapping/window.h"

namespace trav::mapping {
namespace {

using Clock = std::chrono::steady_clock;
const std::string kFused = "fused";
constexpr int kMinimumPoints = 10;

double Milliseconds(Clock::time_point since) {
  return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

}  // namespace

void BgkUpdate(double m_pre, double variance_pre, double t_s, double decay_rate, double epsilon,
               float* m, float* variance, float* t0_s) {
  if (std::isnan(*m)) {
    *m = static_cast<float>(m_pre);
    *variance = static_cast<float>(variance_pre);
    *t0_s = static_cast<float>(t_s);
    return;
  }
  const double w_t = std::exp(-decay_rate * (t_s - *t0_s));
  const double w_sigma = 1.0 / (*variance + epsilon);
  *m = static_cast<float>((w_t * w_sigma * *m + m_pre) / (w_t * w_sigma + 1.0));
  *variance = static_cast<float>((w_t * *variance + variance_pre) / (w_t + 1.0));
  *t0_s = static_cast<float>(t_s);
}

double PreliminaryScore(const FsgpConfig& c, double curvature, double gradient_m,
                        double slope_rad) {
  auto normalised = [](double a, double max) { return std::clamp(a / max, 0.0, 1.0); };
  return c.weight_curvature * normalised(curvature, c.curvature_max) +
         c.weight_gradient * normalised(gradient_m, c.gradient_max_m) +
         c.weight_slope * normalised(slope_rad, c.slope_max_rad);
}

FsgpBgkMapper::FsgpBgkMapper(const FsgpConfig& config)
    : config_(config), hyper_(config.gp), random_(config.seed) {
  ValidateFsgpConfig(config_);
  const common::GridGeometry geometry = common::GridGeometry::Centered(
      Eigen::Vector2d::Zero(), Eigen::Vector2d::Constant(config_.area.map_size_m),
      config_.area.resolution_m);
  map_ = common::GridLayers(
      geometry, {layers::kElevation, layers::kElevationVariance, layers::kSlope, layers::kCurvature,
                 layers::kGradient, layers::kTraversability, layers::kTraversabilityVariance,
                 layers::kLastObserved, layers::kObstacle});
  fused_ = common::GridLayers(geometry, {kFused});
}

MapUpdateResult FsgpBgkMapper::Update(const common::PointCloud& points_W,
                                      const Eigen::Isometry3d& X_WB, double t_s) {
  MapUpdateResult result;
  const Eigen::Vector3d p_WB = X_WB.translation();
  const double half = 0.5 * config_.area.window_m;

  // 1. crop to the window (and drop invalid points and overhangs such as tree crowns)
  auto stage = Clock::now();
  Eigen::Matrix3Xf below_robot;
  Eigen::Matrix3Xf window =
      CropWindow(points_W, p_WB, config_.area.window_m, config_.area.max_height_above_robot_m,
                 &result, config_.max_height_above_ground_m, &below_robot);
  // FSGP-Accumulation: the last N frames' clouds together
  if (config_.accumulate_frames > 1) {
    history_.push_back(window);
    while (static_cast<int>(history_.size()) > config_.accumulate_frames) history_.pop_front();
    Eigen::Index total = 0;
    for (const Eigen::Matrix3Xf& frame : history_) total += frame.cols();
    window.resize(3, total);
    Eigen::Index at = 0;
    for (const Eigen::Matrix3Xf& frame : history_) {
      for (Eigen::Index i = 0; i < frame.cols(); ++i) {
        const Eigen::Vector3f p = frame.col(i);
        if (std::abs(p.x() - p_WB.x()) <= half && std::abs(p.y() - p_WB.y()) <= half)
          window.col(at++) = p;
      }
    }
    window.conservativeResize(3, at);
  }
  result.window_points = static_cast<int>(window.cols());
  result.times.crop = Milliseconds(stage);
  if (window.cols() < kMinimumPoints) {
    result.status = MapUpdateStatus::kTooFewPoints;
    return result;
  }

  // 2-3. features and the training set
  stage = Clock::now();
  const TrainingSet training = ExtractTrainingSet(window, config_, &random_);
  result.training_points = static_cast<int>(training.points_W.cols());
  result.times.features = Milliseconds(stage);
  if (training.points_W.cols() < kMinimumPoints) {
    result.status = MapUpdateStatus::kTooFewPoints;
    return result;
  }

  // 4. inputs (x, y, kappa, g), standardised; optional PCA fitted on the training set
  stage = Clock::now();
  const Eigen::Index m = training.points_W.cols();
  Eigen::MatrixXd raw(m, 4);
  raw.col(0) = training.points_W.row(0).transpose();
  raw.col(1) = training.points_W.row(1).transpose();
  raw.col(2) = training.curvature;
  raw.col(3) = training.gradient;
  const Eigen::RowVector4d mean = raw.colwise().mean();
  const Eigen::RowVector4d scale =
      ((raw.rowwise() - mean).colwise().squaredNorm() / static_cast<double>(m))
          .cwiseSqrt()
          .cwiseMax(1e-3);
  // u = (raw - mean) / scale, then u' = u R (R: PCA rotation or identity)
  Eigen::Matrix4d rotation = Eigen::Matrix4d::Identity();
  Eigen::MatrixXd inputs = (raw.rowwise() - mean).array().rowwise() / scale.array();
  if (config_.pca) {
    const Eigen::Matrix4d covariance = inputs.transpose() * inputs / static_cast<double>(m);
    rotation = Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(covariance).eigenvectors();
    inputs = inputs * rotation;
  }
  // a least-squares plane carries the terrain's trend; the GP models the deviations from it (a
  // constant-mean GP with short length scales bends back to its mean between training points and
  // overestimates slopes by 10-20 %)
  Eigen::MatrixXd design(m, 3);
  design << raw.col(0), raw.col(1), Eigen::VectorXd::Ones(m);
  const Eigen::VectorXd observed = training.points_W.row(2).transpose();
  const Eigen::Vector3d plane = design.colPivHouseholderQr().solve(observed);
  const Eigen::VectorXd heights = observed - design * plane;

  // 5. sparse GP (optionally a few L-BFGS steps on the hyperparameters, warm-started)
  SparseGp::OptimiseHyperparameters(inputs, heights, config_.lbfgs_iterations, &hyper_);
  if (!gp_.Fit(inputs, heights, hyper_)) {
    result.status = MapUpdateStatus::kModelFailed;
    return result;
  }
  result.times.fit = Milliseconds(stage);

  // 6. the window's cells with a training point within the support radius: kappa*, g* by IDW,
  // then the GP's mean, variance and slope
  stage = Clock::now();
  map_.Recenter(p_WB.head<2>());
  fused_.Recenter(p_WB.head<2>());
  const common::GridGeometry& g = map_.geometry();
  const auto [low, high] = WindowCells(g, p_WB, config_.area.window_m);
  Eigen::Matrix2Xd cells(2, (high - low + Eigen::Vector2i::Ones()).prod());
  std::vector<Eigen::Vector2i> cell_index;
  for (int ix = low.x(); ix <= high.x(); ++ix) {
    for (int iy = low.y(); iy <= high.y(); ++iy) {
      cells.col(static_cast<Eigen::Index>(cell_index.size())) = g.CellCenter(ix, iy);
      cell_index.emplace_back(ix, iy);
    }
  }
  Eigen::MatrixXi idw_indices;
  Eigen::MatrixXd idw_weights;
  Eigen::VectorXd nearest;
  InverseDistanceWeights(training.points_W, cells, config_.idw_neighbours, config_.support_radius_m,
                         &idw_indices, &idw_weights, &nearest);
  std::vector<Eigen::Index> supported;
  for (Eigen::Index c = 0; c < cells.cols(); ++c) {
    if (nearest[c] <= config_.support_radius_m) supported.push_back(c);
  }
  const auto t_count = static_cast<Eigen::Index>(supported.size());
  Eigen::MatrixXd test(t_count, 4);
  for (Eigen::Index s = 0; s < t_count; ++s) {
    const Eigen::Index c = supported[static_cast<std::size_t>(s)];
    double curvature = 0.0, gradient = 0.0;
    for (Eigen::Index j = 0; j < idw_indices.rows(); ++j) {
      curvature += idw_weights(j, c) * training.curvature[idw_indices(j, c)];
      gradient += idw_weights(j, c) * training.gradient[idw_indices(j, c)];
    }
    test.row(s) << cells(0, c), cells(1, c), curvature, gradient;
  }
  const Eigen::MatrixXd raw_test = test;
  test = ((test.rowwise() - mean).array().rowwise() / scale.array()).matrix() * rotation;
  Eigen::VectorXd f, variance;
  Eigen::MatrixXd df_du;
  gp_.Predict(test, &f, &df_du);
  // the variance on every n-th cell; the others take it from the cell at the start of their block
  {
    const int stride = config_.variance_stride;
    std::vector<Eigen::Index> sampled;
    for (Eigen::Index s = 0; s < t_count; ++s) {
      const Eigen::Vector2i& cell =
          cell_index[static_cast<std::size_t>(supported[static_cast<std::size_t>(s)])];
      if (cell.x() % stride == 0 && cell.y() % stride == 0) sampled.push_back(s);
    }
    Eigen::MatrixXd sampled_inputs(static_cast<Eigen::Index>(sampled.size()), test.cols());
    for (std::size_t k = 0; k < sampled.size(); ++k)
      sampled_inputs.row(static_cast<Eigen::Index>(k)) = test.row(sampled[k]);
    Eigen::VectorXd sampled_variance;
    gp_.PredictVariance(sampled_inputs, &sampled_variance);
    // the sampled variances on the window's cells (NaN elsewhere), indexed from `low`
    const Eigen::Vector2i window_size = high - low + Eigen::Vector2i::Ones();
    Eigen::MatrixXd block_variance = Eigen::MatrixXd::Constant(
        window_size.x(), window_size.y(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t k = 0; k < sampled.size(); ++k) {
      const Eigen::Vector2i& cell =
          cell_index[static_cast<std::size_t>(supported[static_cast<std::size_t>(sampled[k])])];
      block_variance(cell.x() - low.x(), cell.y() - low.y()) =
          sampled_variance[static_cast<Eigen::Index>(k)];
    }
    variance.resize(t_count);
    for (Eigen::Index s = 0; s < t_count; ++s) {
      const Eigen::Vector2i& cell =
          cell_index[static_cast<std::size_t>(supported[static_cast<std::size_t>(s)])];
      const Eigen::Vector2i corner =
          Eigen::Vector2i(cell.x() - cell.x() % stride, cell.y() - cell.y() % stride) - low;
      const double v = (corner.array() >= 0).all() ? block_variance(corner.x(), corner.y())
                                                   : std::numeric_limits<double>::quiet_NaN();
      // a block whose corner cell is unsupported: the prior variance (least certain)
      variance[s] = std::isnan(v) ? gp_.prior_variance() : v;
    }
  }
  // the plane back in, and the slope over x and y only: d f / d x = a + sum_d d f / d u'_d R(x, d)
  // / s_x
  f.array() += plane[0] * raw_test.col(0).array() + plane[1] * raw_test.col(1).array() + plane[2];
  const Eigen::VectorXd df_dx = (df_du * rotation.row(0).transpose() / scale[0]).array() + plane[0];
  const Eigen::VectorXd df_dy = (df_du * rotation.row(1).transpose() / scale[1]).array() + plane[1];
  result.times.predict = Milliseconds(stage);

  // 7-8. preliminary score and fusion per world cell
  stage = Clock::now();
  Eigen::MatrixXf& fused = fused_.Layer(kFused);
  Eigen::MatrixXf& fused_variance = map_.Layer(layers::kTraversabilityVariance);
  Eigen::MatrixXf& last = map_.Layer(layers::kLastObserved);
  for (Eigen::Index s = 0; s < t_count; ++s) {
    const Eigen::Vector2i& cell =
        cell_index[static_cast<std::size_t>(supported[static_cast<std::size_t>(s)])];
    const double slope = std::atan(std::hypot(df_dx[s], df_dy[s]));
    const double score = PreliminaryScore(config_, raw_test(s, 2), raw_test(s, 3), slope);
    map_.Layer(layers::kElevation)(cell.x(), cell.y()) = static_cast<float>(f[s]);
    map_.Layer(layers::kElevationVariance)(cell.x(), cell.y()) = static_cast<float>(variance[s]);
    map_.Layer(layers::kSlope)(cell.x(), cell.y()) = static_cast<float>(slope);
    map_.Layer(layers::kCurvature)(cell.x(), cell.y()) = static_cast<float>(raw_test(s, 2));
    map_.Layer(layers::kGradient)(cell.x(), cell.y()) = static_cast<float>(raw_test(s, 3));
    float& m_cell = fused(cell.x(), cell.y());
    float& v_cell = fused_variance(cell.x(), cell.y());
    float& t_cell = last(cell.x(), cell.y());
    if (config_.fuse) {
      BgkUpdate(score, variance[s], t_s, config_.decay_rate, config_.variance_epsilon, &m_cell,
                &v_cell, &t_cell);
    } else {
      m_cell = static_cast<float>(score);
      v_cell = static_cast<float>(variance[s]);
      t_cell = static_cast<float>(t_s);
    }
  }
  result.observed_cells = static_cast<int>(t_count);
  result.times.fusion = Milliseconds(stage);

  // 9. normalised Gaussian smoothing over the known cells of the window
  stage = Clock::now();
  Smooth(low, high);
  MarkObstacles(below_robot, low, high);
  result.times.smoothing = Milliseconds(stage);
  return result;
}

namespace {

// Morphological closing (dilation, then erosion) of a mask by the 3 x 3 cell square.
Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> ClosedMask(
    const Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>& mask) {
  const Eigen::Index nx = mask.rows(), ny = mask.cols();
  auto neighbourhood = [&](const Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>& in, bool all) {
    Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> result(nx, ny);
    for (Eigen::Index ix = 0; ix < nx; ++ix) {
      for (Eigen::Index iy = 0; iy < ny; ++iy) {
        bool value = all;
        for (Eigen::Index jx = std::max<Eigen::Index>(0, ix - 1); jx <= std::min(nx - 1, ix + 1);
             ++jx) {
          for (Eigen::Index jy = std::max<Eigen::Index>(0, iy - 1); jy <= std::min(ny - 1, iy + 1);
               ++jy) {
            value = all ? (value && in(jx, jy)) : (value || in(jx, jy));
          }
        }
        result(ix, iy) = value;
      }
    }
    return result;
  };
  return neighbourhood(neighbourhood(mask, false), true);
}

}  // namespace

void FsgpBgkMapper::MarkObstacles(const Eigen::Matrix3Xf& below_robot, const Eigen::Vector2i& low,
                                  const Eigen::Vector2i& high) {
  // the faces the height regression cannot see (their points were cropped as not terrain): the
  // latest observation of each cell decides, so a cell seen free again clears
  const Eigen::MatrixXf seen =
      ObstacleCells(below_robot, map_.geometry(), low, high, config_.max_height_above_ground_m);
  Eigen::MatrixXf& obstacle = map_.Layer(layers::kObstacle);
  Eigen::MatrixXf& out = map_.Layer(layers::kTraversability);
  for (int ix = low.x(); ix <= high.x(); ++ix) {
    for (int iy = low.y(); iy <= high.y(); ++iy) {
      const float value = seen(ix - low.x(), iy - low.y());
      if (!std::isnan(value)) obstacle(ix, iy) = value;
    }
  }
  // closed by one cell: faces seen edge-on or occluded leave gaps of a cell or two in a wall,
  // never a passage. A cleared cell that the regression has never scored keeps its 1 (sparse
  // views of a real obstacle clear more often than movers do, and movers are kept out of the
  // frames). Only cells near the window can change: the closing there (the obstacle layer changed
  // in the window only) and the smoothed cost in the window and its margin; everywhere else the
  // previous frames already wrote the closed mask, so the result equals closing the whole map.
  const common::GridGeometry& g = map_.geometry();
  const int margin = std::max(SmoothingRadiusCells(), 2);
  const Eigen::Vector2i out_low = (low.array() - margin).max(0);
  const Eigen::Vector2i out_high =
      (high.array() + margin).min(Eigen::Array2i(g.num_x - 1, g.num_y - 1));
  // the closing of a cell reads the mask two cells around it
  const Eigen::Vector2i mask_low = (out_low.array() - 2).max(0);
  const Eigen::Vector2i mask_high =
      (out_high.array() + 2).min(Eigen::Array2i(g.num_x - 1, g.num_y - 1));
  const Eigen::Vector2i size = mask_high - mask_low + Eigen::Vector2i::Ones();
  const Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> lethal =
      ClosedMask(obstacle.block(mask_low.x(), mask_low.y(), size.x(), size.y()).array() == 1.0f);
  for (int ix = out_low.x(); ix <= out_high.x(); ++ix) {
    for (int iy = out_low.y(); iy <= out_high.y(); ++iy) {
      if (lethal(ix - mask_low.x(), iy - mask_low.y())) out(ix, iy) = 1.0f;
    }
  }
}

int FsgpBgkMapper::SmoothingRadiusCells() const {
  return config_.smoothing_sigma_m > 0.0
             ? static_cast<int>(
                   std::floor(config_.smoothing_radius_m / map_.geometry().resolution_m + 1e-9))
             : 0;
}

void FsgpBgkMapper::Smooth(const Eigen::Vector2i& low, const Eigen::Vector2i& high) {
  const common::GridGeometry& g = map_.geometry();
  const Eigen::MatrixXf& fused = fused_.Layer(kFused);
  Eigen::MatrixXf& out = map_.Layer(layers::kTraversability);
  const int radius = SmoothingRadiusCells();
  const double inverse_two_sigma2 =
      config_.smoothing_sigma_m > 0.0
          ? 1.0 / (2.0 * config_.smoothing_sigma_m * config_.smoothing_sigma_m)
          : 0.0;
  // the window and a margin of `radius` cells (their neighbourhoods changed)
  for (int ix = std::max(0, low.x() - radius); ix <= std::min(g.num_x - 1, high.x() + radius);
       ++ix) {
    for (int iy = std::max(0, low.y() - radius); iy <= std::min(g.num_y - 1, high.y() + radius);
         ++iy) {
      if (std::isnan(fused(ix, iy))) continue;
      double sum = 0.0, weights = 0.0;
      for (int dx = -radius; dx <= radius; ++dx) {
        for (int dy = -radius; dy <= radius; ++dy) {
          const int jx = ix + dx, jy = iy + dy;
          if (!g.Contains(jx, jy) || std::isnan(fused(jx, jy))) continue;
          const double d2 = (dx * dx + dy * dy) * g.resolution_m * g.resolution_m;
          if (d2 > config_.smoothing_radius_m * config_.smoothing_radius_m + 1e-12) continue;
          const double w = std::exp(-d2 * inverse_two_sigma2);
          sum += w * fused(jx, jy);
          weights += w;
        }
      }
      out(ix, iy) = static_cast<float>(sum / weights);
    }
  }
}

}  // namespace trav::mapping
