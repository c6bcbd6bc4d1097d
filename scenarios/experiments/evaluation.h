#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "scenarios/experiments/job_array.h"
#include "scenarios/run/run_metrics.h"

namespace trav::scenarios {

/// What `trav eval` evaluates: the paper's mapping evaluation (docs/evaluation.md). Every scene
/// is a world of one terrain type with its own seed, a route planned on its ground truth and
/// driven by the closed loop on the ground-truth oracle, scanned by the MID-360 with 15 %
/// occlusion; every method is fed the same frames and scored against the ground truth over the
/// cells observed so far, frame by frame.
struct EvalOptions {
  /// Terrain types (names as in scenario files), one table row each.
  std::vector<std::string> terrains{"hilly", "forest", "ruin", "road", "indoor"};
  int scenes{2};          ///< scenes per terrain type, >= 1
  std::uint64_t seed{1};  ///< scene k (from 0) of a type has terrain seed seed + k
  /// Methods: sgp, fsgp, fsgp-bgk, fsgp-accumulation, em; the ablations of the paper's
  /// contributions fsgp-bgk-no-features (no (kappa, g) GP inputs) and fsgp-bgk-fixed-gain (a
  /// fixed-gain filter at FSGP-BGK's mean weight of the scene); and, to check the evaluation
  /// itself, ground-truth (the oracle: the truth at every observed cell) and constant=C (C at every
  /// observed cell, C in [0, 1]).
  std::vector<std::string> methods{"sgp", "fsgp", "fsgp-bgk", "fsgp-accumulation", "em"};
  /// The paper's inducing-point ablation of the GP mappers among `methods` (sgp, fsgp, fsgp-bgk):
  /// each count other than the scenes' own M (mapping key max_training_points, 500) adds a method
  /// <method>-m<count> (fsgp-bgk-m50); empty: no ablation.
  std::vector<int> inducing_points{50, 125, 500};
  /// Pose sources of the mappers besides the true pose (localization methods other than `true`:
  /// drift-model, scan-matching): each adds <method>@<source> for every mapper of `methods`, run
  /// on the drive's frames moved into the odometry frame of that source's pose estimate along the
  /// drive (the drift model fed the true poses, the LiDAR odometry the drive's scans; the drive
  /// itself navigates on the true pose). Empty: the true pose only.
  std::vector<std::string> pose_sources;
  /// The ground truth the maps are scored against (docs/ground-truth.md): "physical" (the robot
  /// resting on the world at 16 headings against its measured limits; untraversable: cost 1) or
  /// "geometric" (the mapper's score formula on exact heights; untraversable: cost at or above the
  /// planner's lethal threshold). Routes and drives use the geometric one either way.
  std::string truth{"physical"};
  double route_length_m{24.0};  ///< straight-line distance from start to goal [m], > 0
  int max_frames{0};            ///< LiDAR frames per scene, 0: until the drive ends; >= 0
  /// Scenario overrides applied to every scene (key.path=value, as `trav run --set`).
  std::vector<std::string> sets;
  int jobs{1};                      ///< scenes run at once (worker processes), >= 1
  double scene_time_limit_s{3600};  ///< a scene running longer is killed and recorded [s], > 0
};

/// Checks every option. @throws common::InputError naming the flag and value.
void ValidateEvalOptions(const EvalOptions& options);

/// The options as stored in the output folder's options.json, and back.
/// @throws common::InputError (naming `source`) if a field is missing or of the wrong type.
nlohmann::json EvalOptionsJson(const EvalOptions& options);
EvalOptions EvalOptionsFromJson(const nlohmann::json& json, const std::string& source);

/// True if two option sets give the same scenes and records (jobs and time limit aside): a
/// folder evaluated with one can be resumed with the other.
bool SameEvaluation(const EvalOptions& a, const EvalOptions& b);

/// One scene: a terrain type and a terrain seed.
struct EvalScene {
  std::string terrain;
  std::uint64_t seed{0};
  std::string Id() const { return terrain + "-" + std::to_string(seed); }
};

/// The scenes of an evaluation, terrain by terrain, in seed order.
std::vector<EvalScene> EvalScenes(const EvalOptions& options);

/// The methods every scene runs: `options.methods`, the floor and the ceiling of every table
/// (constant=0.5 unless a constant is listed, and the ground-truth oracle), then the ablation's
/// <method>-m<count>, then per pose source <method>@<source>.
std::vector<std::string> EvalMethods(const EvalOptions& options);

/// The inducing-point count M of the GP mappers in the scenes (the mapping default unless
/// overridden).
int BaseInducingPoints(const EvalOptions& options);

/// A method of the inducing-point ablation: a GP mapper at another inducing-point count.
struct AblationMethod {
  std::string base;  ///< sgp, fsgp or fsgp-bgk
  int inducing_points{0};
  /// The method's name: <base>-m<inducing_points>.
  std::string Name() const { return base + "-m" + std::to_string(inducing_points); }
};

/// The ablation method named `method` (sgp-m50, fsgp-m50, fsgp-bgk-m50), if it is one.
std::optional<AblationMethod> ParseAblationMethod(const std::string& method);

/// The GP mappers the ablation covers: those of sgp, fsgp and fsgp-bgk among `options.methods`,
/// in their order there (none without inducing-point counts).
std::vector<std::string> AblatedMethods(const EvalOptions& options);

/// A method on another pose source: a mapper of `methods` fed the frames in the odometry frame of
/// the source's pose estimate.
struct PoseSourceMethod {
  std::string base;    ///< the mapper (sgp, fsgp, fsgp-bgk, fsgp-accumulation, em)
  std::string source;  ///< the localization method's name (drift-model, scan-matching)
  /// The method's name: <base>@<source>.
  std::string Name() const { return base + "@" + source; }
};

/// The pose-source method named `method` (fsgp-bgk@drift-model), if it is one.
std::optional<PoseSourceMethod> ParsePoseSourceMethod(const std::string& method);

/// The mappers each pose source runs: the standard mappers among `options.methods` (not the
/// oracle, constants or the contribution ablations), in their order there.
std::vector<std::string> PoseSourceMappers(const EvalOptions& options);

/// One method's frames in a scene, frame by frame (every vector has one value per frame).
struct EvalFrames {
  std::vector<double> t_s;  ///< simulation time of the frame [s]
  /// Mean and variance of the error over the compared cells (none: no cell compared yet).
  std::vector<std::optional<double>> mean_error;
  std::vector<std::optional<double>> error_variance;
  std::vector<int> compared_cells;  ///< observed cells the map knows
  std::vector<int> observed_cells;  ///< cells observed so far
  std::vector<double> runtime_ms;   ///< CPU time of the update (thread CPU clock) [ms]
  std::vector<double> wall_ms;      ///< wall time of the update [ms]
  std::vector<double> heap_mb;      ///< heap growth since the method was built [MiB]
};

/// The record's "frames" object (a missing error is null), and back.
void to_json(nlohmann::json& json, const EvalFrames& frames);
void from_json(const nlohmann::json& json, EvalFrames& frames);

/// One method's record in a scene.
struct EvalMethodRecord {
  /// Mean over the scored frames (those with a compared cell) of the frame's mean error and of its
  /// error variance (none: no frame scored).
  std::optional<double> mean_error;
  std::optional<double> error_variance;
  int scored_frames{0};
  /// Median CPU time of an update (thread CPU clock; also written as cpu_ms_median) [ms].
  double runtime_ms_median{0.0};
  double runtime_ms_max{0.0};  ///< largest CPU time of an update [ms]
  double wall_ms_median{0.0};  ///< median wall time of an update [ms]
  /// Mean over frames of the BGK uncertainty weight w_sigma (unset for methods without BGK).
  std::optional<double> mean_fusion_weight;
  double peak_memory_mb{0.0};  ///< largest heap growth [MiB]
  double coverage{0.0};        ///< compared / observed cells after the last frame
  /// The final map's hazard scores (ScoreHazards: AUROC, average precision, Spearman, elevation
  /// RMSE over the observed cells; untraversable: truth cost >= the planner's lethal threshold).
  HazardScores hazards;
  EvalFrames frames;
};

/// The record's object of a method (a missing error is null), and back.
void to_json(nlohmann::json& json, const EvalMethodRecord& record);
void from_json(const nlohmann::json& json, EvalMethodRecord& record);

/// The route of a scene, drawn on its ground truth.
struct EvalRoute {
  std::array<double, 3> start{};  ///< x, y [m], yaw [rad]
  std::array<double, 2> goal{};   ///< x, y [m]
  double optimal_length_m{0.0};   ///< the simplified A* path on the ground truth
  double length_m{0.0};  ///< start to goal in a straight line (--route-length, or shorter) [m]
  int draws{0};          ///< routes drawn until one had a path (all of them for no_route)
};

/// The record's "route" object, and back.
void to_json(nlohmann::json& json, const EvalRoute& route);
void from_json(const nlohmann::json& json, EvalRoute& route);

/// How the drive of a scene ended.
struct EvalDrive {
  std::string outcome;  ///< the Outcome's name, or "no_route" (no route had a path)
  double sim_time_s{0.0};
  double distance_m{0.0};
  std::size_t frames{0};            ///< LiDAR frames recorded
  long long ground_truth_cells{0};  ///< cells of the ground truth's grid
};

/// The record's "drive" object, and back.
void to_json(nlohmann::json& json, const EvalDrive& drive);
void from_json(const nlohmann::json& json, EvalDrive& drive);

/// A finished scene: scenes/<id>.json.
struct EvalSceneRecord {
  std::string id;  ///< EvalScene::Id
  std::string terrain;
  std::uint64_t seed{0};
  EvalRoute route;
  EvalDrive drive;
  std::map<std::string, EvalMethodRecord> methods;  ///< by method name
};

/// scenes/<id>.json's object, and back (how a resumed evaluation reads its finished scenes).
/// @throws nlohmann::json::exception on a missing field or a field of another type.
void to_json(nlohmann::json& json, const EvalSceneRecord& record);
void from_json(const nlohmann::json& json, EvalSceneRecord& record);

/// Runs one scene and returns its record: the route, the drive's outcome, and per method the
/// per-frame error, observed and compared cells, update time and heap growth, with the scene's
/// summary (mean over frames of the mean error and of the error variance, median update time, peak
/// heap growth). Methods run one after the other on the recorded frames, so each is timed alone and
/// its memory is its own.
/// A scene where no route has a path (16 headings at the full, three-quarter and half route length)
/// ends in seconds with drive outcome "no_route" and no methods.
/// @throws common::InputError on a bad override or terrain.
EvalSceneRecord RunEvalScene(const EvalOptions& options, const EvalScene& scene,
                             const std::string& robot_model_path);

/// How an evaluation ended.
struct EvalRunResult {
  int scenes{0};    ///< in the evaluation
  int resumed{0};   ///< finished before this run and kept
  int finished{0};  ///< finished by this run
  int failed{0};    ///< crashed, timed out or failed in this run (recorded under failed/)
  bool interrupted{false};
  std::string slurm_job;  ///< the Slurm job id when submitted there
};

/// Runs the evaluation into `out_dir`: options.json, scenes/<id>.json per finished scene (written
/// atomically by worker jobs `trav_executable eval-scene OUT TERRAIN SEED`, their output in
/// logs/<id>.log), failed/<id>.json per failed scene (RecordJobEnd), then the report. The jobs run
/// as local processes, options.jobs at a time, or with `slurm` as a Slurm job array (without
/// `slurm->wait` it returns once submitted, and `trav eval --collect` writes the report later).
/// Finished scenes (records that read back as EvalSceneRecord) are kept: rerunning into the same
/// folder redoes only the others.
/// `progress_bar`: redraw one line on stderr, else one line per scene.
/// @throws common::InputError if the options are invalid or `out_dir` holds an evaluation with
/// other options; std::runtime_error if Slurm refuses the job.
EvalRunResult RunEvaluation(const EvalOptions& options, const std::string& out_dir,
                            const std::string& trav_executable, const std::string& command_line,
                            bool progress_bar, const std::optional<SlurmOptions>& slurm);

/// Writes the report (WriteEvalReport) of the evaluation in `out_dir` from the scenes finished
/// so far and the failure records. @returns the number of finished scenes it read.
int WriteEvalReportFromFolder(const std::string& out_dir, const EvalOptions& options,
                              const std::string& command_line);

/// Writes the report of the evaluation in `out_dir` from what has finished (after a Slurm job
/// submitted without waiting); returns the number of finished scenes.
/// @throws common::InputError if `out_dir` has no options.json.
int CollectEvaluation(const std::string& out_dir);

/// The worker's side: runs one scene of the evaluation in `out_dir` (its options.json) and writes
/// scenes/<id>.json atomically. @throws common::InputError if options.json is missing or bad.
void RunEvalSceneInFolder(const std::string& out_dir, const EvalScene& scene,
                          const std::string& models_dir);

}  // namespace trav::scenarios
