#include "mapping/fsgp_bgk_mapper.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "common/stopwatch.h"

namespace trav::mapping {
namespace {

const std::string kFused = "fused";
constexpr int kMinimumPoints = 10;

}  // namespace

void FsgpBgkMapper::StandardiseInputs(const TrainingSet& training) {
  // inputs (x, y, kappa, g), standardised; optional PCA fitted on the training set
  GpInputs& gp = inputs_;
  const Eigen::Index m = training.points_W.cols();
  auto inputs = gp.inputs.Resize(m, 4);
  inputs.col(0) = training.points_W.row(0).transpose();
  inputs.col(1) = training.points_W.row(1).transpose();
  inputs.col(2) = training.curvature;
  inputs.col(3) = training.gradient;
  gp.mean = inputs.colwise().mean();
  gp.scale = ((inputs.rowwise() - gp.mean).colwise().squaredNorm() / static_cast<double>(m))
                 .cwiseSqrt()
                 .cwiseMax(1e-3);
  // u = (raw - mean) / scale, then u' = u R (R: PCA rotation or identity)
  gp.rotation = Eigen::Matrix4d::Identity();
  inputs = ((inputs.rowwise() - gp.mean).array().rowwise() / gp.scale.array()).matrix();
  if (config_.pca) {
    // the product straight into a fixed-size matrix: inside the quotient Eigen would evaluate it
    // into a heap temporary first
    Eigen::Matrix4d covariance;
    covariance.noalias() = inputs.transpose() * inputs;
    covariance /= static_cast<double>(m);
    gp.rotation = Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(covariance).eigenvectors();
    for (Eigen::Index i = 0; i < m; ++i) inputs.row(i) = inputs.row(i) * gp.rotation;
  }
  // a least-squares plane carries the terrain's trend; the GP models the deviations from it (a
  // constant-mean GP with short length scales bends back to its mean between training points and
  // overestimates slopes by 10-20 %). Normal equations in coordinates centred on the training
  // points' mean: well conditioned, and solved on the stack.
  const Eigen::Vector3d mean_W = training.points_W.rowwise().mean();
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d moment = Eigen::Vector2d::Zero();
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Vector3d d = training.points_W.col(i) - mean_W;
    normal += d.head<2>() * d.head<2>().transpose();
    moment += d.head<2>() * d.z();
  }
  const Eigen::Vector2d slope = normal.ldlt().solve(moment);
  gp.plane << slope, mean_W.z() - slope.dot(mean_W.head<2>());
  auto heights = gp.heights.Resize(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    heights[i] = training.points_W(2, i) - (gp.plane[0] * training.points_W(0, i) +
                                            gp.plane[1] * training.points_W(1, i) + gp.plane[2]);
  }
}

double BgkUpdate(double m_pre, double variance_pre, double t_s, double decay_rate, double epsilon,
                 double fixed_gain, float* m, float* variance, float* t0_s,
                 std::optional<double> reference_variance) {
  if (std::isnan(*m)) {
    *m = static_cast<float>(m_pre);
    *variance = static_cast<float>(variance_pre);
    *t0_s = static_cast<float>(t_s);
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double w_t = std::exp(-decay_rate * (t_s - *t0_s));
  double w_sigma = 1.0 / (*variance + epsilon);
  if (fixed_gain > 0.0) {
    w_sigma = fixed_gain;
  } else if (reference_variance) {
    constexpr double kFloor = 1e-12;
    w_sigma = 2.0 / (epsilon * ((*variance + kFloor) / (*reference_variance + kFloor) + 1.0));
  }
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
  map_ = common::GridLayers(geometry, layers::All());
  fused_ = common::GridLayers(geometry, {kFused});
  if (config_.accumulate_frames > 1)
    history_.resize(static_cast<std::size_t>(config_.accumulate_frames));
}

common::ScratchMatrix<float, 3>::ConstView FsgpBgkMapper::AccumulateFrames(
    const Eigen::Ref<const Eigen::Matrix3Xf>& window, const Eigen::Vector3d& p_WB) {
  const double half = 0.5 * config_.area.window_m;
  const std::size_t frames = history_.size();
  history_[history_next_ % frames].Resize(3, window.cols()) = window;
  ++history_next_;
  // the stored frames, oldest first
  const std::size_t first = history_next_ - std::min(history_next_, frames);
  Eigen::Index total = 0;
  for (std::size_t k = first; k < history_next_; ++k) total += history_[k % frames].cols();
  auto accumulated = accumulated_.Resize(3, total);
  Eigen::Index at = 0;
  for (std::size_t k = first; k < history_next_; ++k) {
    const auto frame = history_[k % frames].view();
    for (Eigen::Index i = 0; i < frame.cols(); ++i) {
      const Eigen::Vector3f p = frame.col(i);
      if (std::abs(p.x() - p_WB.x()) <= half && std::abs(p.y() - p_WB.y()) <= half)
        accumulated.col(at++) = p;
    }
  }
  accumulated_.Resize(3, at);
  return accumulated_.const_view();
}

std::unique_ptr<FsgpBgkMapper> FsgpBgkMapper::UnfusedOf(const FsgpBgkMapper& source) {
  FsgpConfig config = source.config_;
  config.fuse = false;
  auto unfused = std::make_unique<FsgpBgkMapper>(config);
  unfused->source_ = &source;
  return unfused;
}

std::unique_ptr<FsgpBgkMapper> FsgpBgkMapper::OnFeaturesOf(const FsgpBgkMapper& source,
                                                           int max_training_points) {
  FsgpConfig config = source.config_;
  config.max_training_points = max_training_points;
  auto sampling = std::make_unique<FsgpBgkMapper>(config);
  // the mapper that computes the features, which `source` may read in turn
  const FsgpBgkMapper* owner = &source;
  while (owner->source_ != nullptr || owner->features_source_ != nullptr)
    owner = owner->source_ != nullptr ? owner->source_ : owner->features_source_;
  sampling->features_source_ = owner;
  return sampling;
}

void FsgpBgkMapper::ExpectSameFrame(const FsgpBgkMapper& source, double t_s,
                                    const Eigen::Vector3d& p_WB, const char* made_by) {
  if (source.regression_.t_s != t_s || source.regression_.p_WB != p_WB) {
    throw std::logic_error(std::string("FsgpBgkMapper::") + made_by +
                           ": the source did not update on this frame");
  }
}

const WindowCrop& FsgpBgkMapper::FrameCrop() const {
  return features_source_ != nullptr ? features_source_->crop_ : crop_;
}

void FsgpBgkMapper::Regress(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB,
                            double t_s) {
  const common::ThreadCpuStopwatch cpu;
  regression_ = Regression{};
  regression_.t_s = t_s;
  regression_.p_WB = p_WB;
  regression_.result.status = RegressionSteps(points_W, p_WB);
  regression_.cpu_ms = cpu.ElapsedMilliseconds();
}

bool FsgpBgkMapper::CropAndFeatures(const common::PointCloud& points_W,
                                    const Eigen::Vector3d& p_WB) {
  MapUpdateResult& result = regression_.result;
  const common::ThreadCpuStopwatch cpu;
  // 1. crop to the window (and drop invalid points and overhangs such as tree crowns)
  common::Stopwatch stage;
  crop_.Crop(points_W, p_WB, config_.area.window_m, config_.area.max_height_above_robot_m,
             config_.area.GroundCropHeight(), &result);
  crop_.KeepNearFloor(map_, config_.area.GroundCropHeight());
  // FSGP-Accumulation: the last N frames' clouds together
  const common::ScratchMatrix<float, 3>::ConstView window =
      config_.accumulate_frames > 1 ? AccumulateFrames(crop_.window(), p_WB) : crop_.window();
  result.window_points = static_cast<int>(window.cols());
  result.times.crop = stage.ElapsedMilliseconds();
  if (window.cols() < kMinimumPoints) return false;
  // 2. the voxel centroids and their features
  stage.Restart();
  extractor_.ComputeFeatures(window, config_);
  result.times.features = stage.ElapsedMilliseconds();
  regression_.featured = true;
  regression_.features_cpu_ms = cpu.ElapsedMilliseconds();
  regression_.features_wall_ms = result.times.crop + result.times.features;
  return true;
}

MapUpdateStatus FsgpBgkMapper::RegressionSteps(const common::PointCloud& points_W,
                                               const Eigen::Vector3d& p_WB) {
  MapUpdateResult& result = regression_.result;
  if (features_source_ == nullptr) {
    if (!CropAndFeatures(points_W, p_WB)) return MapUpdateStatus::kTooFewPoints;
  } else {
    // the source's crop and features of this frame, and what they took
    ExpectSameFrame(*features_source_, regression_.t_s, p_WB, "OnFeaturesOf");
    const Regression& featured = features_source_->regression_;
    result.input_points = featured.result.input_points;
    result.dropped_invalid = featured.result.dropped_invalid;
    result.window_points = featured.result.window_points;
    if (!featured.featured) return MapUpdateStatus::kTooFewPoints;
    result.shared_cpu_ms = featured.features_cpu_ms;
    result.shared_wall_ms = featured.features_wall_ms;
  }

  // 3. the training set, sampled from the features
  common::Stopwatch stage;
  const TrainingSet training = extractor_.SelectFrom(
      features_source_ != nullptr ? features_source_->extractor_ : extractor_, config_, &random_);
  result.training_points = static_cast<int>(training.points_W.cols());
  result.times.features += stage.ElapsedMilliseconds();
  if (training.points_W.cols() < kMinimumPoints) {
    return MapUpdateStatus::kTooFewPoints;
  }

  // 4-5. inputs and the sparse GP (optionally a few L-BFGS steps on the hyperparameters,
  // warm-started)
  stage.Restart();
  StandardiseInputs(training);
  SparseGp::OptimiseHyperparameters(inputs_.inputs.view(), inputs_.heights.view(),
                                    config_.lbfgs_iterations, &hyper_);
  if (!gp_.Fit(inputs_.inputs.view(), inputs_.heights.view(), hyper_)) {
    return MapUpdateStatus::kModelFailed;
  }
  result.times.fit = stage.ElapsedMilliseconds();

  // 6. the window's cells with a training point within the support radius: their prediction, on
  // the map as Update recentres it
  stage.Restart();
  const common::GridGeometry geometry = map_.geometry().RecenteredOn(p_WB.head<2>());
  std::tie(regression_.low, regression_.high) = WindowCells(geometry, p_WB, config_.area.window_m);
  PredictCells(geometry, training, regression_.low, regression_.high);
  result.times.predict = stage.ElapsedMilliseconds();
  return MapUpdateStatus::kUpdated;
}

MapUpdateResult FsgpBgkMapper::Update(const common::PointCloud& points_W,
                                      const Eigen::Isometry3d& X_WB, double t_s) {
  const Eigen::Vector3d p_WB = X_WB.translation();
  MapUpdateResult result;
  if (source_ == nullptr) {
    Regress(points_W, p_WB, t_s);
    result = regression_.result;
  } else {
    // the source's regression, its time shared: all of it, and what it shared in turn
    ExpectSameFrame(*source_, t_s, p_WB, "UnfusedOf");
    const Regression& shared = source_->regression_;
    const StageTimes& times = shared.result.times;
    result = shared.result;
    result.times = StageTimes{};
    result.shared_cpu_ms = shared.cpu_ms + shared.result.shared_cpu_ms;
    result.shared_wall_ms =
        times.crop + times.features + times.fit + times.predict + shared.result.shared_wall_ms;
  }
  const FsgpBgkMapper& regressed = source_ != nullptr ? *source_ : *this;
  const Regression& regression = regressed.regression_;
  if (result.status != MapUpdateStatus::kUpdated) return result;

  // 7-8. preliminary score and fusion per world cell
  common::Stopwatch stage;
  map_.Recenter(p_WB.head<2>());
  fused_.Recenter(p_WB.head<2>());
  result.mean_fusion_weight = Fuse(regressed.prediction_, t_s);
  result.observed_cells = static_cast<int>(regressed.prediction_.cells.size());
  result.times.fusion = stage.ElapsedMilliseconds();

  // 9. normalised Gaussian smoothing over the known cells of the window
  stage.Restart();
  Smooth(regression.low, regression.high);
  if (config_.area.obstacle_layer) {
    // the smoothed cost changed in the window and its margin: the closing must be redone there
    obstacles_.Mark(regressed.FrameCrop(), regression.low, regression.high, config_.area, p_WB, t_s,
                    std::max(SmoothingRadiusCells(), 2), &map_);
  }
  result.times.smoothing = stage.ElapsedMilliseconds();
  return result;
}

void FsgpBgkMapper::UseHelperThread() {
  if (!helper_) helper_ = std::make_unique<common::HelperThread>();
}

void FsgpBgkMapper::PredictCells(const common::GridGeometry& g, const TrainingSet& training,
                                 const Eigen::Vector2i& low, const Eigen::Vector2i& high) {
  // kappa*, g* by IDW on the cells with a training point within the support radius
  PredictionScratch& s = scratch_;
  auto centres = s.centres_W.Resize(2, (high - low + Eigen::Vector2i::Ones()).prod());
  s.window_cells.clear();
  for (int ix = low.x(); ix <= high.x(); ++ix) {
    for (int iy = low.y(); iy <= high.y(); ++iy) {
      centres.col(static_cast<Eigen::Index>(s.window_cells.size())) = g.CellCenter(ix, iy);
      s.window_cells.emplace_back(ix, iy);
    }
  }
  idw_.Compute(training.points_W, centres, config_.idw_neighbours, config_.support_radius_m);
  const auto idw_indices = idw_.indices();
  const auto idw_weights = idw_.weights();
  const auto nearest = idw_.nearest_m();
  CellPrediction& prediction = prediction_;
  prediction.cells.clear();
  s.supported.clear();
  for (Eigen::Index c = 0; c < centres.cols(); ++c) {
    if (nearest[c] > config_.support_radius_m) continue;
    s.supported.push_back(c);
    prediction.cells.push_back(s.window_cells[static_cast<std::size_t>(c)]);
  }
  const auto t_count = static_cast<Eigen::Index>(s.supported.size());
  auto raw = prediction.raw_inputs.Resize(t_count, 4);
  for (Eigen::Index t = 0; t < t_count; ++t) {
    const Eigen::Index c = s.supported[static_cast<std::size_t>(t)];
    double curvature = 0.0, gradient = 0.0;
    for (Eigen::Index j = 0; j < idw_indices.rows(); ++j) {
      curvature += idw_weights(j, c) * training.curvature[idw_indices(j, c)];
      gradient += idw_weights(j, c) * training.gradient[idw_indices(j, c)];
    }
    raw.row(t) << centres(0, c), centres(1, c), curvature, gradient;
  }
  // then the GP's mean, variance and slope
  auto test = s.test.Resize(t_count, 4);
  test = ((raw.rowwise() - inputs_.mean).array().rowwise() / inputs_.scale.array()).matrix();
  for (Eigen::Index t = 0; t < t_count; ++t) test.row(t) = test.row(t) * inputs_.rotation;
  auto elevation = prediction.elevation.Resize(t_count);
  auto df_du = s.df_du.Resize(t_count, 4);
  auto variance = prediction.variance.Resize(t_count);
  // the mean and the variance only read the fitted GP and write outputs of their own
  common::RunAlongside(
      helper_.get(), [&] { gp_.Predict(test, elevation, df_du); },
      [&] {
        variance_.Compute(gp_, prediction.cells, test, low, high, config_.variance_stride,
                          variance);
      });
  // the plane back in, and the slope over x and y only: d f / d x = a + sum_d d f / d u'_d R(x, d)
  // / s_x
  const Eigen::Vector3d& plane = inputs_.plane;
  auto df_dx = prediction.df_dx.Resize(t_count);
  auto df_dy = prediction.df_dy.Resize(t_count);
  for (Eigen::Index t = 0; t < t_count; ++t) {
    elevation[t] += plane[0] * raw(t, 0) + plane[1] * raw(t, 1) + plane[2];
    df_dx[t] = df_du.row(t).dot(inputs_.rotation.row(0)) / inputs_.scale[0] + plane[0];
    df_dy[t] = df_du.row(t).dot(inputs_.rotation.row(1)) / inputs_.scale[1] + plane[1];
  }
}

double FsgpBgkMapper::Fuse(const CellPrediction& prediction, double t_s) {
  const auto raw_test = prediction.raw_inputs.view();
  const auto elevation = prediction.elevation.view();
  const auto variances = prediction.variance.view();
  const auto df_dx = prediction.df_dx.view();
  const auto df_dy = prediction.df_dy.view();
  double weight_sum = 0.0;
  int weights = 0;
  Eigen::MatrixXf& fused = fused_.Layer(kFused);
  Eigen::MatrixXf& fused_variance = map_.Layer(layers::kTraversabilityVariance);
  Eigen::MatrixXf& last = map_.Layer(layers::kLastObserved);
  Eigen::MatrixXf& elevation_m = map_.Layer(layers::kElevation);
  Eigen::MatrixXf& elevation_variance = map_.Layer(layers::kElevationVariance);
  Eigen::MatrixXf& slope_rad = map_.Layer(layers::kSlope);
  Eigen::MatrixXf& curvature = map_.Layer(layers::kCurvature);
  Eigen::MatrixXf& gradient_m = map_.Layer(layers::kGradient);
  // the uncertainty weight's reference for every cell of the frame (the prediction's: per cell)
  std::optional<double> frame_reference;
  if (config_.variance_reference == VarianceReference::kFrameMean && variances.size() > 0) {
    frame_reference = variances.mean();
  }
  const bool per_cell_reference = config_.variance_reference == VarianceReference::kPrediction;
  for (std::size_t k = 0; k < prediction.cells.size(); ++k) {
    const auto s = static_cast<Eigen::Index>(k);
    const Eigen::Vector2i& cell = prediction.cells[k];
    const double variance = variances[s];
    const double slope = std::atan(std::hypot(df_dx[s], df_dy[s]));
    const double score = PreliminaryScore(config_, raw_test(s, 2), raw_test(s, 3), slope);
    elevation_m(cell.x(), cell.y()) = static_cast<float>(elevation[s]);
    elevation_variance(cell.x(), cell.y()) = static_cast<float>(variance);
    slope_rad(cell.x(), cell.y()) = static_cast<float>(slope);
    curvature(cell.x(), cell.y()) = static_cast<float>(raw_test(s, 2));
    gradient_m(cell.x(), cell.y()) = static_cast<float>(raw_test(s, 3));
    float& m_cell = fused(cell.x(), cell.y());
    float& v_cell = fused_variance(cell.x(), cell.y());
    float& t_cell = last(cell.x(), cell.y());
    if (config_.fuse) {
      const double w_sigma = BgkUpdate(
          score, variance, t_s, config_.decay_rate, config_.variance_epsilon, config_.fixed_gain,
          &m_cell, &v_cell, &t_cell, per_cell_reference ? variance : frame_reference);
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
