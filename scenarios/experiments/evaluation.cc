#include "scenarios/experiments/evaluation.h"

#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "common/enum_names.h"
#include "common/input_error.h"
#include "common/logging.h"
#include "common/random.h"
#include "common/statistics.h"
#include "common/stopwatch.h"
#include "common/yaml_reader.h"
#include "mapping/fsgp_bgk_mapper.h"
#include "mapping/lidar_odometry.h"
#include "mapping/traversability_mapper.h"
#include "scenarios/experiments/eval_report.h"
#include "scenarios/experiments/job_array.h"
#include "scenarios/run/closed_loop.h"
#include "scenarios/run/mappers.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/process_pool.h"
#include "scenarios/run/run_metrics.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

constexpr const char* kConstantPrefix = "constant=";
// The ablations of the paper's two contributions: FSGP-BGK without its (kappa, g) GP inputs, and
// with a fixed-gain filter (the mean BGK weight of the scene) in place of the uncertainty weight.
constexpr const char* kNoFeatures = "fsgp-bgk-no-features";
constexpr const char* kFixedGain = "fsgp-bgk-fixed-gain";
// A feature length scale that makes the kernel constant along the feature (standardised units).
constexpr double kIgnoredLengthScale = 1e4;
// The floor of every table: a constant map ranks nothing (AUROC 0.5).
constexpr const char* kFloorMethod = "constant=0.5";
// The drive outcome of a scene whose route draws all failed (no methods run).
constexpr const char* kNoRoute = "no_route";
// The GP mappers of the paper's inducing-point ablation.
constexpr const char* kGpMethods[] = {"sgp", "fsgp", "fsgp-bgk"};
constexpr int kRouteDraws = 16;
// The route's length as a fraction of --route-length, tried in turn when no heading has a path.
constexpr double kRouteLengths[] = {1.0, 0.75, 0.5};
constexpr double kBytesPerMiB = 1024.0 * 1024.0;
// The ground truths a scene is scored against (EvalOptions::truth).
constexpr const char* kPhysicalTruth = "physical";
constexpr const char* kGeometricTruth = "geometric";

// What the maps of a scene are scored against: the truth's layers and the cost from which a cell
// is untraversable (the physical truth's 1, the geometric truth's the planner's lethal threshold).
struct ScoringTruth {
  common::GridLayers layers;
  double untraversable_cost{1.0};
};

// The scene scenario of a terrain type before its route: 50 x 50 m like the paper's scenes, the
// MID-360 with 15 % of each frame occluded as in the paper's evaluation, a rolling map large
// enough to hold the whole world (the paper scores the global map), and the closed loop on the
// ground-truth oracle so that every method sees the same frames.
std::string SceneYaml(const std::string& terrain, std::uint64_t seed) {
  // indoor: finer height field for thin walls, doors wide enough for the robot at 0.2 m
  const bool indoor = terrain == "indoor";
  std::ostringstream yaml;
  yaml << "schema_version: 1\n"
       << "name: eval_" << terrain << "_" << seed << "\n"
       << "mode: navigate\n"
       << "terrain: {type: " << terrain << ", seed: " << seed << ", size: [50, 50], resolution: "
       << (indoor ? "0.05, parameters: {door_width: 1.5, min_room_size: 5}" : "0.1") << "}\n"
       << "lidar: {occlusion: 0.15}\n"
       << "mapping: {method: ground-truth, map_size: 60}\n"
       << "duration: 90\n"
       << "video: {enabled: false}\n";
  return yaml.str();
}

// The scenario of a scene with the evaluation's overrides (its route still to be drawn).
Scenario SceneScenario(const EvalOptions& options, const EvalScene& scene) {
  common::YamlDocument document =
      common::YamlDocument::Parse(SceneYaml(scene.terrain, scene.seed), "eval scene " + scene.Id());
  ApplyOverrides(options.sets, &document);
  return LoadScenario(document);
}

bool StartsWith(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

// The value C of a method "constant=C", or nothing if it is not one. @throws common::InputError
// if C is not a number in [0, 1].
std::optional<float> ConstantOf(const std::string& method) {
  if (!StartsWith(method, kConstantPrefix)) return std::nullopt;
  const std::string text = method.substr(std::string(kConstantPrefix).size());
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(value >= 0.0 && value <= 1.0)) {
    throw common::InputError("--methods", method, "constant=C needs a number C in [0, 1]");
  }
  return static_cast<float>(value);
}

// The mapper method of a standard method name, or nothing.
std::optional<MapperMethod> StandardMethod(const std::string& name) {
  for (const MapperMethod method :
       {MapperMethod::kSgp, MapperMethod::kFsgp, MapperMethod::kFsgpBgk,
        MapperMethod::kFsgpAccumulation, MapperMethod::kElevationMap, MapperMethod::kGroundTruth}) {
    if (name == common::NameOf(method)) return method;
  }
  return std::nullopt;
}

// A mapper that paints every observed cell of the ground truth's grid with the truth (the
// oracle) or with a constant: what checks that the evaluation scores exactly what it should.
class PaintingMapper : public mapping::TraversabilityMapper {
 public:
  PaintingMapper(const common::GridLayers& truth_W, const mapping::MapArea& area,
                 std::optional<float> constant)
      : truth_(truth_W.Layer(mapping::layers::kTraversability)),
        constant_(constant),
        observed_(truth_W.geometry(), area),
        map_(truth_W.geometry(), {mapping::layers::kTraversability}) {}

  mapping::MapUpdateResult Update(const common::PointCloud& points_W, const Eigen::Isometry3d& X_WB,
                                  double) override {
    const std::size_t before = observed_.cells().size();
    mapping::MapUpdateResult result;
    result.input_points = static_cast<int>(points_W.size());
    result.observed_cells = observed_.Add(points_W, X_WB.translation());
    Eigen::MatrixXf& layer = map_.Layer(mapping::layers::kTraversability);
    for (std::size_t i = before; i < observed_.cells().size(); ++i) {
      const Eigen::Vector2i& cell = observed_.cells()[i];
      layer(cell.x(), cell.y()) = constant_ ? *constant_ : truth_(cell.x(), cell.y());
    }
    return result;
  }

  const common::GridLayers& map() const override { return map_; }

 private:
  const Eigen::MatrixXf& truth_;
  std::optional<float> constant_;
  ObservedCells observed_;
  common::GridLayers map_;
};

// The mapper of `method` for a scene.
std::unique_ptr<mapping::TraversabilityMapper> MakeEvalMapper(const std::string& method,
                                                              const Scenario& scene,
                                                              const common::GridLayers& truth_W,
                                                              double fixed_gain) {
  if (const std::optional<float> constant = ConstantOf(method)) {
    return std::make_unique<PaintingMapper>(truth_W, scene.mapping.area, constant);
  }
  Scenario configured = scene;
  const std::optional<PoseSourceMethod> on_source = ParsePoseSourceMethod(method);
  if (on_source) {
    configured.mapper = common::NameOf(*StandardMethod(on_source->base));
  } else if (method == kNoFeatures || method == kFixedGain) {
    configured.mapper = common::NameOf(MapperMethod::kFsgpBgk);
    if (method == kNoFeatures) {
      configured.mapping.gp.length_scales.tail<2>().setConstant(kIgnoredLengthScale);
    } else {
      configured.mapping.fixed_gain = fixed_gain;
    }
  } else if (const std::optional<AblationMethod> ablation = ParseAblationMethod(method)) {
    configured.mapper = common::NameOf(*StandardMethod(ablation->base));
    configured.mapping.max_training_points = ablation->inducing_points;
  } else {
    configured.mapper = common::NameOf(*StandardMethod(method));
  }
  if (UsesGroundTruthMap(configured)) {
    return std::make_unique<PaintingMapper>(truth_W, scene.mapping.area, std::nullopt);
  }
  return MakeMapper(configured, on_source ? MapperPose::kEstimated : MapperPose::kTrue);
}

// Heap in use by this process [bytes]: every arena's allocated chunks and mmapped blocks.
double HeapInUseBytes() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<double>(info.uordblks) + static_cast<double>(info.hblkhd);
}

// A LiDAR frame recorded during the drive, in the mapper's frame M: W on the true pose, the
// odometry frame O of a pose estimate on another pose source.
struct RecordedFrame {
  common::PointCloud cloud_M;
  Eigen::Isometry3d X_MB;
  double t_s;
};

// A LiDAR frame as the sensor reported it, for an odometry on the scans: the points in L with their
// times, the sensor's true pose at the frame's end, and the base's rotation the gyroscope measured
// since the previous frame.
struct RecordedScan {
  common::PointCloud points_L;
  Eigen::Isometry3d X_WL_end;
  std::optional<Eigen::Matrix3d> R_turn_B;
};

// Records every LiDAR frame as the mapper gets it (movers removed) and, with `scans`, as the sensor
// reported it.
class FrameRecorder : public LoopObserver {
 public:
  FrameRecorder(std::vector<RecordedFrame>* frames, std::vector<RecordedScan>* scans)
      : frames_(frames), scans_(scans) {}
  bool WantsPoints() const override { return true; }
  void OnLidarFrame(const ClosedLoop& loop, const lidar::LidarFrame& frame,
                    const Eigen::Matrix3Xf& /*points_W*/) override {
    if (scans_ == nullptr) return;
    std::optional<Eigen::Matrix3d> turn;
    if (loop.imu() != nullptr) turn = gyro_turn_B_;
    scans_->push_back({frame.points_L, frame.X_WL_end, turn});
    gyro_turn_B_.setIdentity();
  }
  void OnMapInput(const ClosedLoop& /*loop*/, const common::PointCloud& cloud_O,
                  const Eigen::Isometry3d& X_OB, double t_s) override {
    frames_->push_back({cloud_O, X_OB, t_s});
  }
  void OnPhysicsStep(const ClosedLoop& loop, const LoopStep& /*step*/) override {
    if (scans_ != nullptr && loop.imu() != nullptr) {
      gyro_turn_B_ =
          sim::IntegrateGyro(gyro_turn_B_, loop.imu()->samples(), loop.scenario().imu.rate_hz);
    }
  }

 private:
  std::vector<RecordedFrame>* frames_;
  std::vector<RecordedScan>* scans_;
  Eigen::Matrix3d gyro_turn_B_{Eigen::Matrix3d::Identity()};
};

// The drift model's estimates X_OB at the frames of a drive on the true pose, the model fed the
// drive's true poses frame by frame (its drift grows with the distance between them, as along the
// physics steps).
std::vector<Eigen::Isometry3d> DriftModelPoses(const std::vector<RecordedFrame>& frames_W,
                                               const sim::PoseNoiseConfig& localization) {
  sim::PoseNoise estimator(localization);
  std::vector<Eigen::Isometry3d> X_OB;
  for (const RecordedFrame& frame : frames_W) {
    common::RobotState truth;
    truth.time_s = frame.t_s;
    truth.X_WB = frame.X_MB;
    X_OB.push_back(estimator.Estimate(truth).X_WB);
  }
  return X_OB;
}

// The LiDAR odometry's estimates X_OB at the frames of a drive, run on the drive's scans (with the
// gyroscope's rotations when the IMU recorded them), O where the sensor ended the first frame.
std::vector<Eigen::Isometry3d> ScanMatchingPoses(const std::vector<RecordedFrame>& frames_W,
                                                 const std::vector<RecordedScan>& scans,
                                                 const Scenario& scene) {
  std::vector<Eigen::Isometry3d> X_OB;
  if (scans.empty()) return X_OB;
  mapping::LidarOdometry odometry(scene.lidar_odometry, scans.front().X_WL_end);
  for (std::size_t k = 0; k < scans.size() && k < frames_W.size(); ++k) {
    const Eigen::Isometry3d X_BL = frames_W[k].X_MB.inverse() * scans[k].X_WL_end;
    std::optional<Eigen::Matrix3d> R_turn;
    if (scans[k].R_turn_B) R_turn = X_BL.linear().transpose() * *scans[k].R_turn_B * X_BL.linear();
    const Eigen::Isometry3d& X_OL =
        odometry.AddScan(scans[k].points_L.points, scans[k].points_L.time_offsets,
                         scene.lidar.frame_period_s, R_turn);
    X_OB.push_back(X_OL * X_BL.inverse());
  }
  return X_OB;
}

// The frames of a drive on the true pose as a mapper on a pose estimate gets them: each moved into
// the estimate's odometry frame O (X_OW = X_OB X_WB^-1), with the base at X_OB.
std::vector<RecordedFrame> FramesOnPoses(const std::vector<RecordedFrame>& frames_W,
                                         const std::vector<Eigen::Isometry3d>& X_OB) {
  std::vector<RecordedFrame> frames_O;
  frames_O.reserve(frames_W.size());
  for (std::size_t k = 0; k < frames_W.size() && k < X_OB.size(); ++k) {
    const RecordedFrame& frame = frames_W[k];
    const Eigen::Isometry3f X_OW = (X_OB[k] * frame.X_MB.inverse()).cast<float>();
    RecordedFrame moved{frame.cloud_M, X_OB[k], frame.t_s};
    moved.cloud_M.points = (X_OW.linear() * frame.cloud_M.points).colwise() + X_OW.translation();
    frames_O.push_back(std::move(moved));
  }
  return frames_O;
}

// A number, or none if it is NaN.
std::optional<double> NumberOrNone(double value) {
  return std::isnan(value) ? std::nullopt : std::optional<double>(value);
}

// What a method reads from another method of the scene instead of computing it (FSGP-BGK
// mappers of the same frames): `source`'s whole regression (an FSGP fusing its FSGP-BGK's,
// FsgpBgkMapper::UnfusedOf) or its crop and features (the ablation at another M,
// FsgpBgkMapper::OnFeaturesOf).
struct SharedWork {
  std::string source;
  bool regression{false};
};

// The cells a set of frames observed (ObservedCells fed them in order) and how many after each
// frame: what every method fed those frames is scored over, computed once for them all.
struct ObservedFrames {
  ObservedCells cells;
  std::vector<int> counts;
  // per frame, for each map geometry asked, the map's cell of each cell observed up to the frame
  // (MapCellIndices): the mappers' maps share a geometry frame by frame (one size and resolution,
  // recentred on the same poses), and their cells are looked up once
  std::vector<std::vector<std::pair<common::GridGeometry, std::vector<int>>>> map_cells;

  const std::vector<int>& MapCells(std::size_t frame, const common::GridGeometry& geometry) {
    if (map_cells.size() < counts.size()) map_cells.resize(counts.size());
    auto& known = map_cells.at(frame);
    for (const auto& [g, indices] : known) {
      if (g == geometry) return indices;
    }
    known.emplace_back(geometry,
                       MapCellIndices(geometry, cells, static_cast<std::size_t>(counts.at(frame))));
    return known.back().second;
  }
};

ObservedFrames ObserveFrames(const common::GridGeometry& geometry, const mapping::MapArea& area,
                             const std::vector<RecordedFrame>& frames) {
  ObservedFrames observed{ObservedCells(geometry, area), {}, {}};
  for (const RecordedFrame& frame : frames) {
    observed.cells.Add(frame.cloud_M, frame.X_MB.translation());
    observed.counts.push_back(static_cast<int>(observed.cells.cells().size()));
  }
  return observed;
}

// One method's mapper and its scores, accumulated frame by frame.
class MethodEvaluation {
 public:
  // `source`: the evaluation of `shared.source`, which updates on each frame first; null with no
  // shared work: a mapper of its own.
  // `observed`: the cells of the frames the method is fed, each in turn.
  MethodEvaluation(const std::string& method, const Scenario& scene, const ScoringTruth& truth,
                   ObservedFrames& observed, double fixed_gain,
                   const std::optional<SharedWork>& shared, const MethodEvaluation* source)
      : truth_(truth), observed_(observed) {
    const double heap_before = HeapInUseBytes();
    const auto* source_mapper =
        source != nullptr ? dynamic_cast<const mapping::FsgpBgkMapper*>(source->mapper_.get())
                          : nullptr;
    if (source_mapper != nullptr && shared->regression) {
      mapper_ = mapping::FsgpBgkMapper::UnfusedOf(*source_mapper);
      regression_source_ = source;
    } else if (source_mapper != nullptr) {
      mapper_ = mapping::FsgpBgkMapper::OnFeaturesOf(*source_mapper,
                                                     ParseAblationMethod(method)->inducing_points);
    } else {
      mapper_ = MakeEvalMapper(method, scene, truth.layers, fixed_gain);
    }
    heap_bytes_ = HeapInUseBytes() - heap_before;
  }

  // Feeds one frame to the mapper and scores its map.
  void Update(const RecordedFrame& frame) {
    const double heap_before = HeapInUseBytes();
    const common::Stopwatch start;
    const common::ThreadCpuStopwatch cpu;
    const mapping::MapUpdateResult update = mapper_->Update(frame.cloud_M, frame.X_MB, frame.t_s);
    // the work it read from another mapper, as if it had done it
    runtime_.push_back(cpu.ElapsedMilliseconds() + update.shared_cpu_ms);
    wall_.push_back(start.ElapsedMilliseconds() + update.shared_wall_ms);
    if (!std::isnan(update.mean_fusion_weight)) {
      weight_sum_ += update.mean_fusion_weight;
      ++weighted_frames_;
    }
    // the cells observed up to this frame, their map cells shared with the other methods (their
    // storage not this method's)
    const std::size_t frame_index = t_.size();
    const int observed = observed_.counts.at(frame_index);
    const double heap_before_cells = HeapInUseBytes();
    const std::vector<int>& map_cells = observed_.MapCells(frame_index, mapper_->map().geometry());
    const double shared_heap = HeapInUseBytes() - heap_before_cells;
    const std::string& layer = mapping::layers::kTraversability;
    const LayerError error = CompareObserved(
        mapper_->map().Layer(layer), truth_.layers.Layer(layer), observed_.cells, map_cells);
    t_.push_back(frame.t_s);
    mean_.push_back(error.known_cells > 0 ? error.mean : std::nan(""));
    variance_.push_back(error.known_cells > 0 ? error.variance : std::nan(""));
    compared_.push_back(error.known_cells);
    observed_count_.push_back(observed);
    if (error.known_cells > 0) {
      mean_sum_ += error.mean;
      variance_sum_ += error.variance;
      ++scored_;
    }
    heap_bytes_ += HeapInUseBytes() - heap_before - shared_heap;
    // a method sharing a regression counts the storage of the mapper that makes it (one sharing
    // the features does not count the crop's and the features' storage it reads)
    const double heap = heap_bytes_ + (regression_source_ ? regression_source_->heap_bytes_ : 0.0);
    peak_heap_ = std::max(peak_heap_, heap);
    heap_mb_.push_back(heap / kBytesPerMiB);
  }

  EvalMethodRecord Record() const {
    EvalMethodRecord record;
    // unscored frames have no error
    record.mean_error = NumberOrNone(scored_ > 0 ? mean_sum_ / scored_ : std::nan(""));
    record.error_variance = NumberOrNone(scored_ > 0 ? variance_sum_ / scored_ : std::nan(""));
    record.scored_frames = scored_;
    record.runtime_ms_median = common::Quantile(runtime_, 0.5);
    record.wall_ms_median = common::Quantile(wall_, 0.5);
    if (weighted_frames_ > 0) record.mean_fusion_weight = weight_sum_ / weighted_frames_;
    // (fed every frame: the cells of them all)
    record.hazards =
        ScoreHazards(mapper_->map(), truth_.layers, observed_.cells, truth_.untraversable_cost);
    record.runtime_ms_max =
        runtime_.empty() ? 0.0 : *std::max_element(runtime_.begin(), runtime_.end());
    record.peak_memory_mb = peak_heap_ / kBytesPerMiB;
    const double last_observed = observed_count_.empty() ? 0.0 : observed_count_.back();
    record.coverage = last_observed > 0 ? compared_.back() / last_observed : 0.0;
    EvalFrames& f = record.frames;
    for (std::size_t i = 0; i < mean_.size(); ++i) {
      f.mean_error.push_back(NumberOrNone(mean_[i]));
      f.error_variance.push_back(NumberOrNone(variance_[i]));
    }
    f.t_s = t_;
    f.compared_cells = compared_;
    f.observed_cells = observed_count_;
    f.runtime_ms = runtime_;
    f.wall_ms = wall_;
    f.heap_mb = heap_mb_;
    return record;
  }

 private:
  const ScoringTruth& truth_;
  ObservedFrames& observed_;
  const MethodEvaluation* regression_source_{nullptr};  // whose regression the mapper fuses
  std::unique_ptr<mapping::TraversabilityMapper> mapper_;
  double heap_bytes_{0.0}, peak_heap_{0.0};  // the heap this method's mapper and scores grew by
  double weight_sum_{0.0};
  int weighted_frames_{0};
  std::vector<double> t_, mean_, variance_, runtime_, wall_, heap_mb_;
  std::vector<int> compared_, observed_count_;
  double mean_sum_{0.0}, variance_sum_{0.0};
  int scored_{0};
};

// The FSGP-BGK method whose regression `method` (FSGP: fsgp, fsgp-m125, fsgp@drift-model) fuses
// without BGK: the same inducing points on the same frames (FsgpBgkMapper::UnfusedOf); nothing for
// any other method.
std::optional<std::string> RegressionSourceOf(const std::string& method) {
  const std::string fsgp = common::NameOf(MapperMethod::kFsgp);
  const std::string fsgp_bgk = common::NameOf(MapperMethod::kFsgpBgk);
  if (method == fsgp) return fsgp_bgk;
  if (const std::optional<AblationMethod> ablation = ParseAblationMethod(method)) {
    if (ablation->base == fsgp) return AblationMethod{fsgp_bgk, ablation->inducing_points}.Name();
  }
  if (const std::optional<PoseSourceMethod> on_source = ParsePoseSourceMethod(method)) {
    if (on_source->base == fsgp) return PoseSourceMethod{fsgp_bgk, on_source->source}.Name();
  }
  return std::nullopt;
}

// What `method` reads from another of `methods`: an FSGP its FSGP-BGK's regression; else an
// FSGP-BGK or FSGP of the ablation (at another M) the crop and features of its method at the base
// count. Nothing when that method is not among `methods`.
std::optional<SharedWork> SharedWorkOf(const std::string& method,
                                       const std::vector<std::string>& methods) {
  auto among = [&](const std::string& name) {
    return std::find(methods.begin(), methods.end(), name) != methods.end();
  };
  if (const std::optional<std::string> source = RegressionSourceOf(method);
      source && among(*source))
    return SharedWork{*source, true};
  const std::optional<AblationMethod> ablation = ParseAblationMethod(method);
  if (ablation &&
      (ablation->base == common::NameOf(MapperMethod::kFsgp) ||
       ablation->base == common::NameOf(MapperMethod::kFsgpBgk)) &&
      among(ablation->base)) {
    return SharedWork{ablation->base, false};
  }
  return std::nullopt;
}

// The method whose work `method` reads in the end (following SharedWorkOf), or `method` itself.
std::string SharingRoot(const std::string& method, const std::vector<std::string>& methods) {
  std::optional<SharedWork> shared = SharedWorkOf(method, methods);
  return shared ? SharingRoot(shared->source, methods) : method;
}

// Feeds the frames to `group` (methods each after the one whose work it reads, SharedWorkOf
// among `methods`), scoring each map after every frame.
std::map<std::string, EvalMethodRecord> EvaluateMethods(
    const std::vector<std::string>& group, const std::vector<std::string>& methods,
    const Scenario& scene, const ScoringTruth& truth, const std::vector<RecordedFrame>& frames,
    ObservedFrames& observed, double fixed_gain) {
  std::map<std::string, const MethodEvaluation*> made;
  std::vector<std::unique_ptr<MethodEvaluation>> evaluations;
  for (const std::string& method : group) {
    const std::optional<SharedWork> shared = SharedWorkOf(method, methods);
    const MethodEvaluation* source = shared ? made.at(shared->source) : nullptr;
    evaluations.push_back(std::make_unique<MethodEvaluation>(method, scene, truth, observed,
                                                             fixed_gain, shared, source));
    made[method] = evaluations.back().get();
  }
  for (const RecordedFrame& frame : frames) {
    for (const std::unique_ptr<MethodEvaluation>& evaluation : evaluations)
      evaluation->Update(frame);
  }
  std::map<std::string, EvalMethodRecord> records;
  for (std::size_t i = 0; i < group.size(); ++i) records[group[i]] = evaluations[i]->Record();
  return records;
}

// The methods of `methods` not in `done` that read `method`'s work in the end (SharingRoot),
// `method` first and each after the method whose work it reads.
std::vector<std::string> SharingGroup(const std::string& method,
                                      const std::vector<std::string>& methods,
                                      const std::map<std::string, EvalMethodRecord>& done) {
  std::vector<std::string> group{method}, rest;
  for (const std::string& other : methods) {
    if (other != method && done.count(other) == 0 && SharingRoot(other, methods) == method)
      rest.push_back(other);
  }
  // each method's chain of sources leads to `method` within `rest`
  while (!rest.empty()) {
    const auto next = std::find_if(rest.begin(), rest.end(), [&](const std::string& other) {
      return std::find(group.begin(), group.end(), SharedWorkOf(other, methods)->source) !=
             group.end();
    });
    if (next == rest.end()) throw std::logic_error("SharingGroup: a source of " + rest.front());
    group.push_back(*next);
    rest.erase(next);
  }
  return group;
}

// Feeds the frames to one method, scoring its map after every frame.
EvalMethodRecord EvaluateMethod(const std::string& method, const Scenario& scene,
                                const ScoringTruth& truth, const std::vector<RecordedFrame>& frames,
                                ObservedFrames& observed, double fixed_gain) {
  return EvaluateMethods({method}, {method}, scene, truth, frames, observed, fixed_gain).at(method);
}

// The cells that any method's scores read (each set of frames' ObservedFrames): the only cells of
// the ground truth a scene's record depends on.
std::vector<Eigen::Vector2i> ScoredCells(const std::vector<const ObservedFrames*>& frame_sets) {
  const common::GridGeometry& geometry = frame_sets.front()->cells.geometry();
  std::vector<bool> scored(static_cast<std::size_t>(geometry.num_x) * geometry.num_y, false);
  std::vector<Eigen::Vector2i> cells;
  for (const ObservedFrames* observed : frame_sets) {
    for (const Eigen::Vector2i& cell : observed->cells.cells()) {
      const std::size_t index = static_cast<std::size_t>(cell.x() + cell.y() * geometry.num_x);
      if (scored[index]) continue;
      scored[index] = true;
      cells.push_back(cell);
    }
  }
  return cells;
}

// FSGP-BGK's mean uncertainty weight on the scene's frames (from its record when it ran already):
// the gain of the fixed-gain ablation, so that both fuse with the same mean weight.
double SceneMeanWeight(const EvalSceneRecord& record, const Scenario& scene,
                       const ScoringTruth& truth, const std::vector<RecordedFrame>& frames,
                       ObservedFrames& observed) {
  const auto bgk = record.methods.find("fsgp-bgk");
  const EvalMethodRecord measured =
      bgk != record.methods.end() ? bgk->second
                                  : EvaluateMethod("fsgp-bgk", scene, truth, frames, observed, 0.0);
  return measured.mean_fusion_weight.value_or(1.0 / scene.mapping.variance_epsilon);
}

// Draws the route of a scene: start and goal `length` apart through the world's centre at a
// random heading, until A* finds a path between them on the ground truth (the world is generated
// with obstacles kept clear of both), kRouteDraws headings at each length of kRouteLengths in turn.
// Sets the scenario's start and goal and returns the world drawn with its ground truth, or nothing
// (the scene is recorded as no_route); `route` gets the length and the draws taken.
std::optional<PreparedWorld> DrawRoute(Scenario* scene, double length_m, std::uint64_t seed,
                                       EvalRoute* route) {
  common::Random random(seed);
  for (const double fraction : kRouteLengths) {
    for (int draw = 0; draw < kRouteDraws; ++draw) {
      ++route->draws;
      const double heading = random.Uniform(-M_PI, M_PI);
      const Eigen::Vector2d half =
          0.5 * fraction * length_m * Eigen::Vector2d(std::cos(heading), std::sin(heading));
      scene->start_W.position = -half;
      scene->start_W.yaw = heading;
      scene->goal_W = half;
      if (std::optional<PreparedWorld> routable = RoutableWorld(*scene)) {
        route->length_m = fraction * length_m;
        return routable;
      }
    }
  }
  return std::nullopt;
}

// A finished scene's record, or nothing if it is absent or does not read as one (then it is
// redone).
std::optional<EvalSceneRecord> FinishedScene(const fs::path& path) {
  const std::optional<nlohmann::json> json = ReadJsonIfPresent(path.string());
  if (!json) return std::nullopt;
  try {
    return json->get<EvalSceneRecord>();
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

// Moves an unreadable scene record aside (to <record>.unreadable, or .unreadable-2, ... when that
// exists: never over a file), so that running the scene again replaces nothing of the user's.
void SetAsideUnreadable(const fs::path& record) {
  fs::path aside = record.string() + ".unreadable";
  std::error_code error;
  for (int k = 2; fs::exists(aside, error); ++k) {
    aside = record.string() + ".unreadable-" + std::to_string(k);
  }
  fs::rename(record, aside);
  common::LogStream(common::LogLevel::kWarning)
      << record.string() << " is not a scene record this trav can read: kept as " << aside.string()
      << ", and the scene runs again";
}

// An array of numbers or nulls, and back.
nlohmann::json NumbersOrNulls(const std::vector<std::optional<double>>& values) {
  nlohmann::json array = nlohmann::json::array();
  for (const std::optional<double>& value : values) array.push_back(NumberOrNull(value));
  return array;
}
std::vector<std::optional<double>> OptionalNumbers(const nlohmann::json& json) {
  std::vector<std::optional<double>> values;
  for (const nlohmann::json& value : json.get<std::vector<nlohmann::json>>()) {
    values.push_back(OptionalNumber(value));
  }
  return values;
}

}  // namespace

void ValidateEvalOptions(const EvalOptions& options) {
  if (options.terrains.empty()) throw common::InputError("--terrains", "", "needs a terrain type");
  common::RequireValue(options.scenes >= 1 && options.scenes <= 100000, "--scenes", options.scenes,
                       "must be in [1, 100000]");
  if (options.truth != kPhysicalTruth && options.truth != kGeometricTruth) {
    throw common::InputError("--truth", options.truth, "expected physical or geometric");
  }
  common::RequireValue(options.route_length_m > 0.0 && options.route_length_m <= 40.0,
                       "--route-length", options.route_length_m, "must be in (0, 40] m");
  common::RequireValue(options.max_frames >= 0 && options.max_frames <= 100000, "--frames",
                       options.max_frames, "must be in [0, 100000]");
  common::RequireValue(options.jobs >= 1 && options.jobs <= 1024, "--jobs", options.jobs,
                       "must be in [1, 1024]");
  common::RequireValue(options.scene_time_limit_s > 0.0 && options.scene_time_limit_s <= 1e6,
                       "--time-limit", options.scene_time_limit_s, "must be in (0, 1e6] s");
  if (options.methods.empty()) throw common::InputError("--methods", "", "needs a method");
  std::set<std::string> seen;
  for (const std::string& method : options.methods) {
    if (!seen.insert(method).second) {
      throw common::InputError("--methods", method, "is listed twice");
    }
    if (!StandardMethod(method) && !ConstantOf(method) && method != kNoFeatures &&
        method != kFixedGain) {
      throw common::InputError("--methods", method,
                               "unknown method (expected sgp, fsgp, fsgp-bgk, fsgp-accumulation, "
                               "em, fsgp-bgk-no-features, fsgp-bgk-fixed-gain, ground-truth or "
                               "constant=C)");
    }
  }
  for (const int count : options.inducing_points) {
    common::RequireValue(count >= 10 && count <= 3000, "--inducing", count,
                         "must be in [10, 3000]");
  }
  std::set<std::string> sources;
  for (const std::string& source : options.pose_sources) {
    const std::optional<sim::LocalizationMethod> method =
        common::EnumFromName<sim::LocalizationMethod>(source);
    if (!method || *method == sim::LocalizationMethod::kTrue) {
      throw common::InputError("--pose-sources", source,
                               "unknown pose source (expected drift-model or scan-matching; the "
                               "true pose always runs)");
    }
    if (!sources.insert(source).second) {
      throw common::InputError("--pose-sources", source, "is listed twice");
    }
  }
  std::set<std::string> terrains;
  for (const std::string& terrain : options.terrains) {
    if (!terrains.insert(terrain).second) {
      throw common::InputError("--terrains", terrain, "is listed twice");
    }
    // every scene's scenario must load: the terrain type and every override
    SceneScenario(options, {terrain, options.seed});
  }
}

nlohmann::json EvalOptionsJson(const EvalOptions& options) {
  return {{"terrains", options.terrains},
          {"scenes", options.scenes},
          {"seed", options.seed},
          {"methods", options.methods},
          {"inducing_points", options.inducing_points},
          {"pose_sources", options.pose_sources},
          {"truth", options.truth},
          {"route_length_m", options.route_length_m},
          {"max_frames", options.max_frames},
          {"sets", options.sets},
          {"jobs", options.jobs},
          {"scene_time_limit_s", options.scene_time_limit_s}};
}

EvalOptions EvalOptionsFromJson(const nlohmann::json& json, const std::string& source) {
  EvalOptions options;
  try {
    json.at("terrains").get_to(options.terrains);
    json.at("scenes").get_to(options.scenes);
    json.at("seed").get_to(options.seed);
    json.at("methods").get_to(options.methods);
    json.at("inducing_points").get_to(options.inducing_points);
    // absent in evaluations written before pose sources existed: the true pose only
    options.pose_sources = json.value("pose_sources", std::vector<std::string>{});
    // absent in evaluations written before the physical truth: they were scored on the geometric
    options.truth = json.value("truth", std::string(kGeometricTruth));
    json.at("route_length_m").get_to(options.route_length_m);
    json.at("max_frames").get_to(options.max_frames);
    json.at("sets").get_to(options.sets);
    json.at("jobs").get_to(options.jobs);
    json.at("scene_time_limit_s").get_to(options.scene_time_limit_s);
  } catch (const nlohmann::json::exception& e) {
    throw common::InputError(source, "", std::string("not an evaluation's options: ") + e.what());
  }
  // a stored file is input too: the same bounds as the command line's
  try {
    ValidateEvalOptions(options);
  } catch (const common::InputError& e) {
    throw common::InputError(source, "", e.what());
  }
  return options;
}

bool SameEvaluation(const EvalOptions& a, const EvalOptions& b) {
  return a.terrains == b.terrains && a.scenes == b.scenes && a.seed == b.seed &&
         a.methods == b.methods && a.inducing_points == b.inducing_points &&
         a.pose_sources == b.pose_sources && a.truth == b.truth &&
         a.route_length_m == b.route_length_m && a.max_frames == b.max_frames && a.sets == b.sets;
}

std::vector<EvalScene> EvalScenes(const EvalOptions& options) {
  std::vector<EvalScene> scenes;
  for (const std::string& terrain : options.terrains) {
    for (int k = 0; k < options.scenes; ++k) {
      scenes.push_back({terrain, options.seed + static_cast<std::uint64_t>(k)});
    }
  }
  return scenes;
}

int BaseInducingPoints(const EvalOptions& options) {
  return SceneScenario(options, {options.terrains.front(), options.seed})
      .mapping.max_training_points;
}

std::vector<std::string> EvalMethods(const EvalOptions& options) {
  std::vector<std::string> methods = options.methods;
  // the floor and the ceiling of every table: a constant map and the oracle
  if (std::none_of(methods.begin(), methods.end(),
                   [](const std::string& m) { return StartsWith(m, kConstantPrefix); })) {
    methods.push_back(kFloorMethod);
  }
  if (std::find(methods.begin(), methods.end(), "ground-truth") == methods.end()) {
    methods.push_back("ground-truth");
  }
  const int base = BaseInducingPoints(options);
  for (const std::string& gp_method : AblatedMethods(options)) {
    for (const int count : options.inducing_points) {
      if (count != base) methods.push_back(AblationMethod{gp_method, count}.Name());
    }
  }
  for (const std::string& source : options.pose_sources) {
    for (const std::string& mapper : PoseSourceMappers(options)) {
      methods.push_back(PoseSourceMethod{mapper, source}.Name());
    }
  }
  return methods;
}

std::optional<PoseSourceMethod> ParsePoseSourceMethod(const std::string& method) {
  const std::size_t at = method.find('@');
  if (at == std::string::npos) return std::nullopt;
  PoseSourceMethod parsed{method.substr(0, at), method.substr(at + 1)};
  const std::optional<MapperMethod> mapper = StandardMethod(parsed.base);
  if (!mapper || *mapper == MapperMethod::kGroundTruth ||
      !common::EnumFromName<sim::LocalizationMethod>(parsed.source)) {
    return std::nullopt;
  }
  return parsed;
}

std::vector<std::string> PoseSourceMappers(const EvalOptions& options) {
  std::vector<std::string> mappers;
  for (const std::string& method : options.methods) {
    const std::optional<MapperMethod> mapper = StandardMethod(method);
    if (mapper && *mapper != MapperMethod::kGroundTruth) mappers.push_back(method);
  }
  return mappers;
}

std::optional<AblationMethod> ParseAblationMethod(const std::string& method) {
  const std::size_t at = method.rfind("-m");
  if (at == std::string::npos || at + 2 >= method.size()) return std::nullopt;
  const std::string count = method.substr(at + 2);
  if (count.size() > 6 ||
      !std::all_of(count.begin(), count.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return std::nullopt;
  }
  const std::string base = method.substr(0, at);
  if (std::find(std::begin(kGpMethods), std::end(kGpMethods), base) == std::end(kGpMethods)) {
    return std::nullopt;
  }
  return AblationMethod{base, std::stoi(count)};
}

std::vector<std::string> AblatedMethods(const EvalOptions& options) {
  std::vector<std::string> ablated;
  if (options.inducing_points.empty()) return ablated;
  for (const std::string& method : options.methods) {
    if (std::find(std::begin(kGpMethods), std::end(kGpMethods), method) != std::end(kGpMethods) &&
        std::find(ablated.begin(), ablated.end(), method) == ablated.end()) {
      ablated.push_back(method);
    }
  }
  return ablated;
}

void to_json(nlohmann::json& json, const EvalFrames& f) {
  json = {{"t_s", f.t_s},
          {"mean_error", NumbersOrNulls(f.mean_error)},
          {"error_variance", NumbersOrNulls(f.error_variance)},
          {"compared_cells", f.compared_cells},
          {"observed_cells", f.observed_cells},
          {"runtime_ms", f.runtime_ms},
          {"wall_ms", f.wall_ms},
          {"heap_mb", f.heap_mb}};
}

void from_json(const nlohmann::json& json, EvalFrames& f) {
  json.at("t_s").get_to(f.t_s);
  f.mean_error = OptionalNumbers(json.at("mean_error"));
  f.error_variance = OptionalNumbers(json.at("error_variance"));
  json.at("compared_cells").get_to(f.compared_cells);
  json.at("observed_cells").get_to(f.observed_cells);
  json.at("runtime_ms").get_to(f.runtime_ms);
  json.at("wall_ms").get_to(f.wall_ms);
  json.at("heap_mb").get_to(f.heap_mb);
}

void to_json(nlohmann::json& json, const EvalMethodRecord& r) {
  json = {{"mean_error", NumberOrNull(r.mean_error)},
          {"error_variance", NumberOrNull(r.error_variance)},
          {"scored_frames", r.scored_frames},
          {"runtime_ms_median", r.runtime_ms_median},
          {"runtime_ms_max", r.runtime_ms_max},
          {"cpu_ms_median", r.runtime_ms_median},
          {"wall_ms_median", r.wall_ms_median},
          {"mean_fusion_weight", NumberOrNull(r.mean_fusion_weight)},
          {"peak_memory_mb", r.peak_memory_mb},
          {"coverage", r.coverage},
          {"frames", r.frames}};
  json.update(nlohmann::json(r.hazards));
}

void from_json(const nlohmann::json& json, EvalMethodRecord& r) {
  r.mean_error = OptionalNumber(json.at("mean_error"));
  r.error_variance = OptionalNumber(json.at("error_variance"));
  json.at("scored_frames").get_to(r.scored_frames);
  json.at("runtime_ms_median").get_to(r.runtime_ms_median);
  json.at("runtime_ms_max").get_to(r.runtime_ms_max);
  json.at("wall_ms_median").get_to(r.wall_ms_median);
  // absent in records written before the fusion weight was recorded: unset, as for a non-BGK method
  r.mean_fusion_weight = json.contains("mean_fusion_weight")
                             ? OptionalNumber(json.at("mean_fusion_weight"))
                             : std::nullopt;
  json.at("peak_memory_mb").get_to(r.peak_memory_mb);
  json.at("coverage").get_to(r.coverage);
  json.at("frames").get_to(r.frames);
  json.get_to(r.hazards);
}

void to_json(nlohmann::json& json, const EvalRoute& r) {
  json = {{"start", r.start},
          {"goal", r.goal},
          {"optimal_length_m", r.optimal_length_m},
          {"length_m", r.length_m},
          {"draws", r.draws}};
}

void from_json(const nlohmann::json& json, EvalRoute& r) {
  json.at("start").get_to(r.start);
  json.at("goal").get_to(r.goal);
  json.at("optimal_length_m").get_to(r.optimal_length_m);
  json.at("length_m").get_to(r.length_m);
  json.at("draws").get_to(r.draws);
}

void to_json(nlohmann::json& json, const EvalDrive& d) {
  json = {{"outcome", d.outcome},
          {"sim_time_s", d.sim_time_s},
          {"distance_m", d.distance_m},
          {"frames", d.frames},
          {"ground_truth_cells", d.ground_truth_cells}};
}

void from_json(const nlohmann::json& json, EvalDrive& d) {
  json.at("outcome").get_to(d.outcome);
  json.at("sim_time_s").get_to(d.sim_time_s);
  json.at("distance_m").get_to(d.distance_m);
  json.at("frames").get_to(d.frames);
  json.at("ground_truth_cells").get_to(d.ground_truth_cells);
}

void to_json(nlohmann::json& json, const EvalSceneRecord& r) {
  json = {{"id", r.id},       {"terrain", r.terrain}, {"seed", r.seed},
          {"route", r.route}, {"drive", r.drive},     {"methods", r.methods}};
}

void from_json(const nlohmann::json& json, EvalSceneRecord& r) {
  json.at("id").get_to(r.id);
  json.at("terrain").get_to(r.terrain);
  json.at("seed").get_to(r.seed);
  json.at("route").get_to(r.route);
  json.at("drive").get_to(r.drive);
  json.at("methods").get_to(r.methods);
}

EvalSceneRecord RunEvalScene(const EvalOptions& options, const EvalScene& scene,
                             const std::string& robot_model_path) {
  Scenario scenario = SceneScenario(options, scene);
  EvalSceneRecord record;
  record.id = scene.Id();
  record.terrain = scene.terrain;
  record.seed = scene.seed;
  const std::optional<PreparedWorld> routable =
      DrawRoute(&scenario, options.route_length_m, scene.seed, &record.route);
  if (!routable) {
    record.drive.outcome = kNoRoute;
    return record;
  }
  // the drive: the closed loop on the oracle and the true pose, every frame recorded as the mapper
  // would get it (the pose sources' estimates are made along it afterwards)
  Scenario drive_scenario = scenario;
  drive_scenario.pose_noise = sim::PoseNoiseConfig{};
  const bool scan_matching = std::find(options.pose_sources.begin(), options.pose_sources.end(),
                                       "scan-matching") != options.pose_sources.end();
  std::vector<RecordedFrame> frames;
  std::vector<RecordedScan> scans;
  FrameRecorder recorder(&frames, scan_matching ? &scans : nullptr);
  // on the world the route was drawn on, not built again
  ClosedLoop loop(drive_scenario, {robot_model_path, options.max_frames, false, false, &*routable});
  const RunSummary drive = RunLoop(&loop, {&recorder});

  // each set of frames (the true pose's, each pose source's) and the cells it observed
  const common::GridGeometry& geometry = routable->truth_W.geometry();
  std::map<std::string, std::vector<RecordedFrame>> frames_on_source;
  std::map<std::string, ObservedFrames> observed_on_source;
  ObservedFrames observed = ObserveFrames(geometry, scenario.mapping.area, frames);
  std::vector<const ObservedFrames*> frame_sets{&observed};
  for (const std::string& source : options.pose_sources) {
    sim::PoseNoiseConfig localization = scenario.pose_noise;
    localization.method = *common::EnumFromName<sim::LocalizationMethod>(source);
    frames_on_source[source] =
        FramesOnPoses(frames, localization.method == sim::LocalizationMethod::kScanMatching
                                  ? ScanMatchingPoses(frames, scans, scenario)
                                  : DriftModelPoses(frames, localization));
    observed_on_source.emplace(
        source, ObserveFrames(geometry, scenario.mapping.area, frames_on_source[source]));
    frame_sets.push_back(&observed_on_source.at(source));
  }
  // the physical truth only where a score reads it: 12 to 16 % of the world on 24 m routes
  const std::vector<Eigen::Vector2i> scored_cells = ScoredCells(frame_sets);
  const ScoringTruth truth =
      options.truth == kPhysicalTruth
          ? ScoringTruth{WorldPhysicalTruth(geometry, loop.world(), scenario.ground_truth,
                                            &scored_cells),
                         1.0}
          : ScoringTruth{routable->truth_W, scenario.planner.search.lethal_threshold};
  // an FSGP beside its FSGP-BGK fuses that one's regression, the ablation's FSGP-BGK samples the
  // features of FSGP-BGK at the base M (the same maps at a fraction of the time): each group of
  // methods sharing work fed frame by frame together
  const std::vector<std::string> methods = EvalMethods(options);
  for (const std::string& method : methods) {
    if (record.methods.count(method) > 0) continue;
    const std::vector<std::string> group =
        SharingGroup(SharingRoot(method, methods), methods, record.methods);
    const double fixed_gain =
        method == kFixedGain ? SceneMeanWeight(record, scenario, truth, frames, observed) : 0.0;
    const std::optional<PoseSourceMethod> on_source = ParsePoseSourceMethod(method);
    for (auto& [name, scores] : EvaluateMethods(
             group, methods, scenario, truth,
             on_source ? frames_on_source.at(on_source->source) : frames,
             on_source ? observed_on_source.at(on_source->source) : observed, fixed_gain))
      record.methods[name] = std::move(scores);
  }
  record.route.start = {scenario.start_W.position.x(), scenario.start_W.position.y(),
                        scenario.start_W.yaw};
  record.route.goal = {scenario.goal_W.x(), scenario.goal_W.y()};
  record.route.optimal_length_m = drive.navigation ? drive.navigation->optimal_path_length_m : 0.0;
  record.drive = {common::NameOf(drive.outcome), drive.sim_time_s, drive.distance_m, frames.size(),
                  static_cast<long long>(geometry.num_x) * geometry.num_y};
  return record;
}

void RunEvalSceneInFolder(const std::string& out_dir, const EvalScene& scene,
                          const std::string& models_dir) {
  const fs::path folder(out_dir);
  const fs::path options_path = folder / "options.json";
  const EvalOptions options =
      EvalOptionsFromJson(ReadJsonFile(options_path.string()), options_path.string());
  const Scenario scenario = SceneScenario(options, scene);
  const EvalSceneRecord record = RunEvalScene(options, scene, RobotModelPath(scenario, models_dir));
  WriteTextFileAtomically(folder / "scenes" / (scene.Id() + ".json"),
                          nlohmann::json(record).dump(1) + "\n");
}

EvalRunResult RunEvaluation(const EvalOptions& options, const std::string& out_dir,
                            const std::string& trav_executable, const std::string& command_line,
                            bool progress_bar, const std::optional<SlurmOptions>& slurm) {
  ValidateEvalOptions(options);
  if (slurm) ValidateSlurmOptions(*slurm);
  const CampaignFolder campaign(out_dir, "eval", "options.json", {"scenes"});
  const fs::path folder(out_dir);
  const fs::path options_path = folder / "options.json";
  nlohmann::json stored = EvalOptionsJson(options);
  stored["command"] = command_line;
  campaign.Claim(
      stored,
      [&](const nlohmann::json& previous) {
        return SameEvaluation(EvalOptionsFromJson(previous, options_path.string()), options);
      },
      "the folder holds an evaluation with other options; use another --out, or the same "
      "options to resume it");
  for (const char* sub : {"scenes", "logs", "failed"}) fs::create_directories(folder / sub);

  EvalRunResult result;
  const std::vector<EvalScene> scenes = EvalScenes(options);
  result.scenes = static_cast<int>(scenes.size());
  const fs::path absolute = fs::absolute(folder);
  std::vector<Job> jobs;
  for (const EvalScene& scene : scenes) {
    const fs::path record = absolute / "scenes" / (scene.Id() + ".json");
    if (FinishedScene(record)) {
      ++result.resumed;
      continue;
    }
    // a record there that FinishedScene could not read (cut short, edited, another version)
    std::error_code error;
    if (fs::exists(record, error)) SetAsideUnreadable(record);
    jobs.push_back(FolderJob(absolute.string(), scene.Id(),
                             {trav_executable, "eval-scene", absolute.string(), scene.terrain,
                              std::to_string(scene.seed)},
                             record.string()));
  }
  if (result.resumed > 0) {
    common::LogStream(common::LogLevel::kInfo)
        << result.resumed << " of " << result.scenes << " scenes already finished in " << out_dir
        << ": kept";
  }
  ProgressLine progress(result.scenes, result.resumed, "scene", progress_bar);
  const DispatchEnd ended = DispatchJobs(absolute.string(), jobs, options.scene_time_limit_s,
                                         {options.jobs, slurm, &progress});
  result.slurm_job = ended.slurm_job;
  result.finished = ended.jobs.finished;
  result.failed = ended.jobs.failed;
  result.interrupted = ended.jobs.interrupted;
  if (!ended.waited || result.interrupted) return result;
  WriteEvalReportFromFolder(out_dir, options, command_line);
  return result;
}

int WriteEvalReportFromFolder(const std::string& out_dir, const EvalOptions& options,
                              const std::string& command_line) {
  const fs::path folder(out_dir);
  const std::vector<EvalScene> scenes = EvalScenes(options);
  std::error_code error;
  std::vector<EvalSceneRecord> records;
  std::vector<nlohmann::json> failures;
  for (const EvalScene& scene : scenes) {
    const fs::path path = folder / "scenes" / (scene.Id() + ".json");
    if (std::optional<EvalSceneRecord> record = FinishedScene(path)) {
      records.push_back(std::move(*record));
    } else if (fs::exists(path, error)) {  // there, but FinishedScene could not read it
      // reported, not silently left out (trav eval on the folder runs it again, keeping the file)
      common::LogStream(common::LogLevel::kWarning)
          << path.string() << " is not a scene record this trav can read: left out of the report";
      failures.push_back(
          {{"id", scene.Id()}, {"end", "unreadable record"}, {"log", path.string()}});
    } else if (fs::exists(folder / "failed" / (scene.Id() + ".json"), error)) {
      failures.push_back(ReadJsonFile((folder / "failed" / (scene.Id() + ".json")).string()));
    }
  }
  const nlohmann::json stored = ReadJsonFile((folder / "options.json").string());
  WriteEvalReport(out_dir, options, BaseInducingPoints(options), records, failures,
                  stored.value("command", command_line));
  return static_cast<int>(records.size());
}

int CollectEvaluation(const std::string& out_dir) {
  const CampaignFolder campaign(out_dir, "eval", "options.json", {"scenes"},
                                CampaignFolder::Use::kExisting);
  const fs::path options_path = fs::path(out_dir) / "options.json";
  const EvalOptions options =
      EvalOptionsFromJson(ReadJsonFile(options_path.string()), options_path.string());
  return WriteEvalReportFromFolder(out_dir, options, "");
}

}  // namespace trav::scenarios
