#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "scenarios/experiments/eval_metrics.h"
#include "scenarios/experiments/evaluation.h"

namespace trav::scenarios {

/// One row of results.json: a terrain type and a method over the type's finished scenes.
struct EvalAggregate {
  std::string terrain;
  std::string method;
  int scenes{0};               ///< scenes with at least one scored frame
  int frames{0};               ///< frames over those scenes
  double mean_error{0.0};      ///< mean over scenes of the scene's mean (over frames) error
  double error_variance{0.0};  ///< mean over scenes of the scene's mean error variance
  /// Median CPU time of an update over every frame of every scene (thread CPU clock) [ms]; also
  /// written as cpu_ms_median.
  double runtime_ms_median{0.0};
  double peak_memory_mb{0.0};  ///< largest heap growth of one scene's run [MiB]
  double coverage{0.0};        ///< mean over scenes of the observed cells the map knows at the end
  double wall_ms_median{0.0};  ///< median wall time of an update [ms]
  /// Means over the scenes where each is defined (SceneMetrics); unset where none is.
  std::optional<double> auroc;
  std::optional<double> average_precision;
  std::optional<double> spearman;
  std::optional<double> calibrated_mae;
  std::optional<double> elevation_rmse;
  std::vector<SceneMetrics> scene_values;  ///< per scene of the type
  /// The method the differences are against ("fsgp-bgk"), empty for that method itself.
  std::string paired_with;
  std::vector<PairedDifference> paired;  ///< this method minus paired_with, per metric
};

/// results.json's object of a row, and back. @throws nlohmann::json::exception on a missing field
/// or a field of another type.
void to_json(nlohmann::json& json, const EvalAggregate& row);
void from_json(const nlohmann::json& json, EvalAggregate& row);

/// Aggregates finished scene records (RunEvalScene) per terrain type and method, in the order of
/// `terrains` and `methods`; pairs without a scored scene are left out. The hazard metrics come
/// with their per-scene values and, for every method but `reference` (when it ran), the paired
/// differences against it over the type's scenes.
std::vector<EvalAggregate> AggregateScenes(const std::vector<EvalSceneRecord>& scenes,
                                           const std::vector<std::string>& terrains,
                                           const std::vector<std::string>& methods,
                                           const std::string& reference = "fsgp-bgk");

/// Writes the report of an evaluation into `out_dir`, each file atomically:
/// - results.json: one record per terrain type and method (EvalAggregate's fields: terrain,
///   method, mean_error, error_variance, runtime_ms_median, peak_memory_mb, scenes, frames,
///   coverage), and results.csv with the same rows;
/// - results.md: the paper's Table I (mean error and variance per terrain and method, next to the
///   paper's numbers), Table II (FSGP-BGK against the elevation map), Table III (BGK against
///   accumulation: memory and time), the inducing-point ablation, failed scenes, the command;
/// - error_over_time_<terrain>.csv, .png and .svg: each method's mean error against time,
///   averaged over the type's scenes frame by frame, with their range (<method>_min, _max) as a
///   band;
/// - ablation.csv, ablation_error.png and ablation_runtime.png when the ablation ran.
/// Plots are skipped (and the markdown says so) where gnuplot is missing.
void WriteEvalReport(const std::string& out_dir, const EvalOptions& options,
                     int base_inducing_points, const std::vector<EvalSceneRecord>& scenes,
                     const std::vector<nlohmann::json>& failures, const std::string& command);

}  // namespace trav::scenarios
