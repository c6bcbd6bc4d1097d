#include "mapping/fsgp_bgk_mapper.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "common/stopwatch.h"
#include "mapping/features.h"
#include "mapping/window.h"

namespace trav::mapping {
namespace {

const std::string kFused = "fused";
constexpr int kMinimumPoints = 10;

}  // namespace

FsgpBgkMapper::GpInputs FsgpBgkMapper::StandardisedInputs(const TrainingSet& training, bool pca) {
  // inputs (x, y, kappa, g), standardised; optional PCA fitted on the training set
  GpInputs gp;
  const Eigen::Index m = training.points_W.cols();
  Eigen::MatrixXd raw(m, 4);
  raw.col(0) = training.points_W.row(0).transpose();
  raw.col(1) = training.points_W.row(1).transpose();
  raw.col(2) = training.curvature;
  raw.col(3) = training.gradient;
  gp.mean = raw.colwise().mean();
  gp.scale = ((raw.rowwise() - gp.mean).colwise().squaredNorm() / static_cast<double>(m))
                 .cwiseSqrt()
                 .cwiseMax(1e-3);
  // u = (raw - mean) / scale, then u' = u R (R: PCA rotation or identity)
  gp.rotation = Eigen::Matrix4d::Identity();
  gp.inputs = (raw.rowwise() - gp.mean).array().rowwise() / gp.scale.array();
  if (pca) {
    const Eigen::Matrix4d covariance = gp.inputs.transpose() * gp.inputs / static_cast<double>(m);
    gp.rotation = Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(covariance).eigenvectors();
    gp.inputs = gp.inputs * gp.rotation;
  }
  // a least-squares plane carries the terrain's trend; the GP models the deviations from it (a
  // constant-mean GP with short length scales bends back to its mean between training points and
  // overestimates slopes by 10-20 %)
  Eigen::MatrixXd design(m, 3);
  design << raw.col(0), raw.col(1), Eigen::VectorXd::Ones(m);
  const Eigen::VectorXd observed = training.points_W.row(2).transpose();
  gp.plane = design.colPivHouseholderQr().solve(observed);
  gp.heights = observed - design * gp.plane;
  return gp;
}

double BgkUpdate(double m_pre, double variance_pre, double t_s, double decay_rate, double epsilon,
                 double fixed_gain, float* m, float* variance, float* t0_s) {
  if (std::isnan(*m)) {
    *m = static_cast<float>(m_pre);
    *variance = static_cast<float>(variance_pre);
    *t0_s = static_cast<float>(t_s);
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double w_t = std::exp(-decay_rate * (t_s - *t0_s));
  const double w_sigma = fixed_gain > 0.0 ? fixed_gain : 1.0 / (*variance + epsilon);
  *m = static_cast<float>((w_t * w_sigma * *m + m_pre) / (w_t * w_sigma + 1.0));
  *variance = static_cast<float>((w_t * *variance + variance_pre) / (w_t + 1.0));
  *t0_s = static_cast<float>(t_s);
  return w_sigma;
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

Eigen::Matrix3Xf FsgpBgkMapper::AccumulateFrames(const Eigen::Matrix3Xf& window,
                                                 const Eigen::Vector3d& p_WB) {
  const double half = 0.5 * config_.area.window_m;
  history_.push_back(window);
  while (static_cast<int>(history_.size()) > config_.accumulate_frames) history_.pop_front();
  Eigen::Index total = 0;
  for (const Eigen::Matrix3Xf& frame : history_) total += frame.cols();
  Eigen::Matrix3Xf accumulated(3, total);
  Eigen::Index at = 0;
  for (const Eigen::Matrix3Xf& frame : history_) {
    for (Eigen::Index i = 0; i < frame.cols(); ++i) {
      const Eigen::Vector3f p = frame.col(i);
      if (std::abs(p.x() - p_WB.x()) <= half && std::abs(p.y() - p_WB.y()) <= half)
        accumulated.col(at++) = p;
    }
  }
  accumulated.conservativeResize(3, at);
  return accumulated;
}

MapUpdateResult FsgpBgkMapper::Update(const common::PointCloud& points_W,
                                      const Eigen::Isometry3d& X_WB, double t_s) {
  MapUpdateResult result;
  const Eigen::Vector3d p_WB = X_WB.translation();

  // 1. crop to the window (and drop invalid points and overhangs such as tree crowns)
  common::Stopwatch stage;
  Eigen::Matrix3Xf below_robot;
  Eigen::Matrix3Xf window =
      CropWindow(points_W, p_WB, config_.area.window_m, config_.area.max_height_above_robot_m,
                 &result, config_.area.GroundCropHeight(), &below_robot);
  // FSGP-Accumulation: the last N frames' clouds together
  if (config_.accumulate_frames > 1) window = AccumulateFrames(window, p_WB);
  result.window_points = static_cast<int>(window.cols());
  result.times.crop = stage.ElapsedMilliseconds();
  if (window.cols() < kMinimumPoints) {
    result.status = MapUpdateStatus::kTooFewPoints;
    return result;
  }

  // 2-3. features and the training set
  stage.Restart();
  const TrainingSet training = ExtractTrainingSet(window, config_, &random_);
  result.training_points = static_cast<int>(training.points_W.cols());
  result.times.features = stage.ElapsedMilliseconds();
  if (training.points_W.cols() < kMinimumPoints) {
    result.status = MapUpdateStatus::kTooFewPoints;
    return result;
  }

  // 4-5. inputs and the sparse GP (optionally a few L-BFGS steps on the hyperparameters,
  // warm-started)
  stage.Restart();
  const GpInputs inputs = StandardisedInputs(training, config_.pca);
  SparseGp::OptimiseHyperparameters(inputs.inputs, inputs.heights, config_.lbfgs_iterations,
                                    &hyper_);
  if (!gp_.Fit(inputs.inputs, inputs.heights, hyper_)) {
    result.status = MapUpdateStatus::kModelFailed;
    return result;
  }
  result.times.fit = stage.ElapsedMilliseconds();

  // 6. the window's cells with a training point within the support radius: their prediction
  stage.Restart();
  map_.Recenter(p_WB.head<2>());
  fused_.Recenter(p_WB.head<2>());
  const auto [low, high] = WindowCells(map_.geometry(), p_WB, config_.area.window_m);
  const CellPrediction prediction = PredictCells(training, inputs, low, high);
  result.times.predict = stage.ElapsedMilliseconds();

  // 7-8. preliminary score and fusion per world cell
  stage.Restart();
  result.mean_fusion_weight = Fuse(prediction, t_s);
  result.observed_cells = static_cast<int>(prediction.cells.size());
  result.times.fusion = stage.ElapsedMilliseconds();

  // 9. normalised Gaussian smoothing over the known cells of the window
  stage.Restart();
  Smooth(low, high);
  if (config_.area.obstacle_layer) MarkObstacles(below_robot, low, high);
  result.times.smoothing = stage.ElapsedMilliseconds();
  return result;
}

FsgpBgkMapper::CellPrediction FsgpBgkMapper::PredictCells(const TrainingSet& training,
                                                          const GpInputs& inputs,
                                                          const Eigen::Vector2i& low,
                                                          const Eigen::Vector2i& high) const {
  // kappa*, g* by IDW on the cells with a training point within the support radius
  const common::GridGeometry& g = map_.geometry();
  Eigen::Matrix2Xd centres(2, (high - low + Eigen::Vector2i::Ones()).prod());
  std::vector<Eigen::Vector2i> cell_index;
  for (int ix = low.x(); ix <= high.x(); ++ix) {
    for (int iy = low.y(); iy <= high.y(); ++iy) {
      centres.col(static_cast<Eigen::Index>(cell_index.size())) = g.CellCenter(ix, iy);
      cell_index.emplace_back(ix, iy);
    }
  }
  Eigen::MatrixXi idw_indices;
  Eigen::MatrixXd idw_weights;
  Eigen::VectorXd nearest;
  InverseDistanceWeights(training.points_W, centres, config_.idw_neighbours,
                         config_.support_radius_m, &idw_indices, &idw_weights, &nearest);
  CellPrediction prediction;
  std::vector<Eigen::Index> supported;
  for (Eigen::Index c = 0; c < centres.cols(); ++c) {
    if (nearest[c] > config_.support_radius_m) continue;
    supported.push_back(c);
    prediction.cells.push_back(cell_index[static_cast<std::size_t>(c)]);
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
    test.row(s) << centres(0, c), centres(1, c), curvature, gradient;
  }
  prediction.raw_inputs = test;
  // then the GP's mean, variance and slope
  test = ((test.rowwise() - inputs.mean).array().rowwise() / inputs.scale.array()).matrix() *
         inputs.rotation;
  Eigen::MatrixXd df_du;
  gp_.Predict(test, &prediction.elevation, &df_du);
  prediction.variance = StridedVariance(test, prediction.cells, low, high);
  // the plane back in, and the slope over x and y only: d f / d x = a + sum_d d f / d u'_d R(x, d)
  // / s_x
  const Eigen::Vector3d& plane = inputs.plane;
  prediction.elevation.array() += plane[0] * prediction.raw_inputs.col(0).array() +
                                  plane[1] * prediction.raw_inputs.col(1).array() + plane[2];
  prediction.df_dx =
      (df_du * inputs.rotation.row(0).transpose() / inputs.scale[0]).array() + plane[0];
  prediction.df_dy =
      (df_du * inputs.rotation.row(1).transpose() / inputs.scale[1]).array() + plane[1];
  return prediction;
}

Eigen::VectorXd FsgpBgkMapper::StridedVariance(const Eigen::MatrixXd& test,
                                               const std::vector<Eigen::Vector2i>& cells,
                                               const Eigen::Vector2i& low,
                                               const Eigen::Vector2i& high) const {
  // the variance on every n-th cell; the others take it from the cell at the start of their block
  const int stride = config_.variance_stride;
  const auto t_count = static_cast<Eigen::Index>(cells.size());
  std::vector<Eigen::Index> sampled;
  for (Eigen::Index s = 0; s < t_count; ++s) {
    const Eigen::Vector2i& cell = cells[static_cast<std::size_t>(s)];
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
    const Eigen::Vector2i& cell = cells[static_cast<std::size_t>(sampled[k])];
    block_variance(cell.x() - low.x(), cell.y() - low.y()) =
        sampled_variance[static_cast<Eigen::Index>(k)];
  }
  Eigen::VectorXd variance(t_count);
  for (Eigen::Index s = 0; s < t_count; ++s) {
    const Eigen::Vector2i& cell = cells[static_cast<std::size_t>(s)];
    const Eigen::Vector2i corner =
        Eigen::Vector2i(cell.x() - cell.x() % stride, cell.y() - cell.y() % stride) - low;
    const double v = (corner.array() >= 0).all() ? block_variance(corner.x(), corner.y())
                                                 : std::numeric_limits<double>::quiet_NaN();
    // a block whose corner cell is unsupported: the prior variance (least certain)
    variance[s] = std::isnan(v) ? gp_.prior_variance() : v;
  }
  return variance;
}

double FsgpBgkMapper::Fuse(const CellPrediction& prediction, double t_s) {
  double weight_sum = 0.0;
  int weights = 0;
  Eigen::MatrixXf& fused = fused_.Layer(kFused);
  Eigen::MatrixXf& fused_variance = map_.Layer(layers::kTraversabilityVariance);
  Eigen::MatrixXf& last = map_.Layer(layers::kLastObserved);
  const Eigen::MatrixXd& raw_test = prediction.raw_inputs;
  for (std::size_t k = 0; k < prediction.cells.size(); ++k) {
    const auto s = static_cast<Eigen::Index>(k);
    const Eigen::Vector2i& cell = prediction.cells[k];
    const double variance = prediction.variance[s];
    const double slope = std::atan(std::hypot(prediction.df_dx[s], prediction.df_dy[s]));
    const double score = PreliminaryScore(config_, raw_test(s, 2), raw_test(s, 3), slope);
    map_.Layer(layers::kElevation)(cell.x(), cell.y()) =
        static_cast<float>(prediction.elevation[s]);
    map_.Layer(layers::kElevationVariance)(cell.x(), cell.y()) = static_cast<float>(variance);
    map_.Layer(layers::kSlope)(cell.x(), cell.y()) = static_cast<float>(slope);
    map_.Layer(layers::kCurvature)(cell.x(), cell.y()) = static_cast<float>(raw_test(s, 2));
    map_.Layer(layers::kGradient)(cell.x(), cell.y()) = static_cast<float>(raw_test(s, 3));
    float& m_cell = fused(cell.x(), cell.y());
    float& v_cell = fused_variance(cell.x(), cell.y());
    float& t_cell = last(cell.x(), cell.y());
    if (config_.fuse) {
      const double w_sigma =
          BgkUpdate(score, variance, t_s, config_.decay_rate, config_.variance_epsilon,
                    config_.fixed_gain, &m_cell, &v_cell, &t_cell);
      if (!std::isnan(w_sigma)) {
        weight_sum += w_sigma;
        ++weights;
      }
    } else {
      m_cell = static_cast<float>(score);
      v_cell = static_cast<float>(variance);
      t_cell = static_cast<float>(t_s);
    }
  }
  return weights > 0 ? weight_sum / weights : std::numeric_limits<double>::quiet_NaN();
}

void FsgpBgkMapper::MarkObstacles(const Eigen::Matrix3Xf& below_robot, const Eigen::Vector2i& low,
                                  const Eigen::Vector2i& high) {
  // the smoothed cost changed in the window and its margin: the closing must be redone there
  mapping::MarkObstacles(below_robot, low, high, config_.area.max_height_above_ground_m,
                         std::max(SmoothingRadiusCells(), 2), &map_);
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
