#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/enum_names.h"
#include "scenarios/experiments/job_array.h"

namespace trav::scenarios {

/// One tuned parameter: a scenario key (a number; "name[i]" for an item of a list) and its range.
struct TunedParameter {
  std::string key;  ///< "controller.mpc.state_weights[2]", "controller.mpc.horizon"
  double min{0.0};
  double max{1.0};      ///< > min
  bool log{false};      ///< searched on a log scale (min > 0)
  bool integer{false};  ///< rounded to the nearest integer
};

/// One term of the objective: weight * metric, or weight * |metric - target| with a target.
struct ObjectiveTerm {
  std::string
      metric;  ///< a summary.json number by its dotted path ("tracking.rms_lateral_error_m")
  double weight{1.0};
  std::optional<double> target;
};

/// Derivative-free optimisers of NLopt.
enum class TuneAlgorithm {
  kBobyqa,      ///< LN_BOBYQA: local, quadratic models (the default)
  kNelderMead,  ///< LN_NELDERMEAD: local simplex
  kCrs,         ///< GN_CRS2_LM: global, controlled random search
  kEsch,        ///< GN_ESCH: global, evolutionary
};

/// The names of TuneAlgorithm's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<TuneAlgorithm>, 4> kTuneAlgorithmNames{
    {{TuneAlgorithm::kBobyqa, "bobyqa"},
     {TuneAlgorithm::kNelderMead, "neldermead"},
     {TuneAlgorithm::kCrs, "crs"},
     {TuneAlgorithm::kEsch, "esch"}}};
constexpr const auto& EnumNames(TuneAlgorithm) { return kTuneAlgorithmNames; }

/// The algorithm of a name (bobyqa, neldermead, crs, esch).
/// @throws common::InputError naming --algorithm and the value otherwise.
TuneAlgorithm ParseTuneAlgorithm(const std::string& name);

/// A tuning file (docs/tuning.md).
struct TuneSpec {
  std::string source;
  std::string name;
  std::vector<std::string> scenarios;       ///< scenario files (paths as resolved)
  std::vector<std::string> seeds;           ///< terrain seeds evaluated during the search
  std::vector<std::string> held_out_seeds;  ///< seeds for the final comparison only
  std::vector<std::string> sets;            ///< key.path=value applied to every run
  std::vector<TunedParameter> parameters;
  std::vector<ObjectiveTerm> objective;
  double failure_penalty{100.0};  ///< added per run that does not end as its scenario expects
  TuneAlgorithm algorithm{TuneAlgorithm::kBobyqa};
  int budget{30};              ///< evaluations of the objective during the search, >= 2
  std::uint64_t seed{1};       ///< the global optimisers' random draws
  double time_limit_s{600.0};  ///< per run [s]
};

/// Reads and checks a tuning file: every parameter must be a number in every scenario, every
/// metric a number that summary.json can have. @throws common::InputError naming the file, key
/// and value (unknown key, parameter or metric, empty range, no scenario or seed).
TuneSpec LoadTuneFile(const std::string& path);

/// How the tuning went.
struct TuneResult {
  int evaluations{0};           ///< objective evaluations of the search
  int cached{0};                ///< of those, found already in the folder (resumed)
  std::vector<double> initial;  ///< the scenarios' own values of the parameters
  std::vector<double> best;     ///< the best values found
  double initial_objective{0.0};
  double best_objective{0.0};
  double initial_held_out{0.0};  ///< the objective on the held-out seeds (0 without any)
  double best_held_out{0.0};
  bool interrupted{false};
};

/// Where the runs of a tuning go.
struct TuneExecution {
  int jobs{1};                        ///< local runs at once
  std::optional<SlurmOptions> slurm;  ///< or each evaluation's runs as a Slurm job array
  std::string trav_executable;
};

/// Tunes the parameters: the optimiser proposes values (starting from the scenarios' own), each
/// proposal runs every scenario on every training seed as `trav run` jobs (in parallel, or on
/// Slurm) under candidates/<hash>/, and its objective is the mean over runs of the weighted
/// terms plus the failure penalty per failed run. Then the initial and the best values run on the
/// held-out seeds. Writes into `out_dir`: evaluations.csv, tuned.yaml (the best values as a
/// scenario fragment), report.md, objective.png and parameters.png. Runs already in the folder
/// are reused, so an interrupted tuning resumes where it stopped (the optimiser is deterministic
/// and proposes the same values again). @throws common::InputError if `out_dir` holds another
/// tuning.
TuneResult RunTuning(const TuneSpec& spec, const std::string& out_dir,
                     const TuneExecution& execution);

}  // namespace trav::scenarios
