#include "scenarios/experiments/tuning.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <nlopt.hpp>

#include "common/enum_names.h"
#include "common/input_error.h"
#include "common/logging.h"
#include "common/text.h"
#include "common/yaml_reader.h"
#include "scenarios/experiments/batch.h"
#include "scenarios/experiments/batch_report.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/plots.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

nlopt::algorithm NloptAlgorithm(TuneAlgorithm algorithm) {
  switch (algorithm) {
    case TuneAlgorithm::kBobyqa:
      return nlopt::LN_BOBYQA;
    case TuneAlgorithm::kNelderMead:
      return nlopt::LN_NELDERMEAD;
    case TuneAlgorithm::kCrs:
      return nlopt::GN_CRS2_LM;
    case TuneAlgorithm::kEsch:
      return nlopt::GN_ESCH;
  }
  return nlopt::LN_BOBYQA;
}

// Every metric summary.json can have: the numbers of a summary with every section.
std::set<std::string> KnownMetrics() {
  std::set<std::string> metrics;
  for (const auto& [key, value] : FlattenSummary(nlohmann::json(SummaryWithEverySection()))) {
    metrics.insert(key);
  }
  return metrics;
}

// The scenario document of a run: the file with the tuning's overrides and the seed, resolved so
// that every key (with its default) is present for the parameters to be read and set.
common::YamlDocument ResolvedDocument(const TuneSpec& spec, const std::string& scenario_path,
                                      const std::string& seed) {
  common::YamlDocument document = common::YamlDocument::Load(scenario_path);
  ApplyOverrides(spec.sets, &document);
  document.Set("terrain.seed", seed);
  return common::YamlDocument::Parse(ResolvedScenarioYaml(LoadScenario(document)), scenario_path);
}

// A parameter's value from its normalised coordinate u in [0, 1], and back.
double ValueOf(const TunedParameter& p, double u) {
  u = std::clamp(u, 0.0, 1.0);
  double value = p.log ? std::exp(std::log(p.min) + u * (std::log(p.max) - std::log(p.min)))
                       : p.min + u * (p.max - p.min);
  if (p.integer) value = std::round(value);
  return std::clamp(value, p.min, p.max);
}
double CoordinateOf(const TunedParameter& p, double value) {
  value = std::clamp(value, p.min, p.max);
  return p.log ? (std::log(value) - std::log(p.min)) / (std::log(p.max) - std::log(p.min))
               : (value - p.min) / (p.max - p.min);
}

std::string Number(double value) { return fmt::format("{:.9g}", value); }

// A short stable name for a set of values (FNV-1a of their text).
std::string HashOf(const std::vector<double>& values) {
  std::uint64_t hash = 1469598103934665603ull;
  for (const double value : values) {
    for (const char c : Number(value) + ";") {
      hash = (hash ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    }
  }
  return fmt::format("{:016x}", hash);
}

// The objective of one candidate over a set of seeds, and its terms' means.
struct Evaluation {
  double objective{0.0};
  int runs{0};
  int failures{0};
  std::map<std::string, double> metric_means;  // the objective's metrics over successful runs
  bool interrupted{false};
};

// Runs (or finds) the runs of `values` on `seeds` and scores them.
Evaluation Evaluate(const TuneSpec& spec, const std::vector<double>& values,
                    const std::vector<std::string>& seeds, const fs::path& folder,
                    const TuneExecution& execution) {
  const fs::path candidate = folder / "candidates" / HashOf(values);
  for (const char* sub : {"scenarios", "runs", "logs", "failed"}) {
    fs::create_directories(candidate / sub);
  }
  nlohmann::json parameters = nlohmann::json::object();
  for (std::size_t i = 0; i < values.size(); ++i) parameters[spec.parameters[i].key] = values[i];
  WriteTextFileAtomically((candidate / "parameters.json").string(), parameters.dump(1) + "\n");

  std::vector<std::string> ids;
  std::vector<Job> jobs;
  for (const std::string& scenario_path : spec.scenarios) {
    for (const std::string& seed : seeds) {
      common::YamlDocument document = ResolvedDocument(spec, scenario_path, seed);
      for (std::size_t i = 0; i < values.size(); ++i) {
        document.Set(spec.parameters[i].key, Number(values[i]));
      }
      const Scenario scenario = LoadScenario(document);
      const std::string id = SafeFileName(scenario.name + "_seed-" + seed);
      ids.push_back(id);
      const fs::path summary = candidate / "runs" / id / "summary.json";
      if (ResultExists(summary.string())) continue;
      const fs::path scenario_file = candidate / "scenarios" / (id + ".yaml");
      WriteTextFileAtomically(scenario_file.string(), ResolvedScenarioYaml(scenario));
      jobs.push_back(FolderJob(candidate.string(), id,
                               {execution.trav_executable, "run", scenario_file.string(), "--out",
                                (candidate / "runs" / id).string()},
                               summary.string()));
    }
  }
  Evaluation evaluation;
  evaluation.interrupted = DispatchJobs(candidate.string(), jobs, spec.time_limit_s,
                                        {execution.jobs, execution.slurm, nullptr})
                               .jobs.interrupted;
  if (evaluation.interrupted) return evaluation;

  std::map<std::string, int> metric_counts;
  for (const std::string& id : ids) {
    ++evaluation.runs;
    const std::optional<nlohmann::json> summary =
        ReadJsonIfPresent((candidate / "runs" / id / "summary.json").string());
    const bool success =
        summary && summary->value("outcome", "") == summary->value("expected_outcome", "");
    if (!success) {
      ++evaluation.failures;
      evaluation.objective += spec.failure_penalty;
      continue;
    }
    const std::map<std::string, double> metrics = FlattenSummary(*summary);
    for (const ObjectiveTerm& term : spec.objective) {
      const auto it = metrics.find(term.metric);
      if (it == metrics.end()) {
        evaluation.objective += spec.failure_penalty;  // a metric the run does not report
        continue;
      }
      const double value = term.target ? std::abs(it->second - *term.target) : it->second;
      evaluation.objective += term.weight * value;
      evaluation.metric_means[term.metric] += it->second;
      ++metric_counts[term.metric];
    }
  }
  for (auto& [metric, sum] : evaluation.metric_means) sum /= metric_counts[metric];
  if (evaluation.runs > 0) evaluation.objective /= evaluation.runs;
  return evaluation;
}

// The best values as a scenario fragment: each tuned key's whole value (all of a list).
std::string TunedYaml(const TuneSpec& spec, const std::vector<double>& values) {
  common::YamlDocument document =
      ResolvedDocument(spec, spec.scenarios.front(), spec.seeds.front());
  for (std::size_t i = 0; i < values.size(); ++i) {
    document.Set(spec.parameters[i].key, Number(values[i]));
  }
  common::YamlDocument fragment = common::YamlDocument::Empty("tuned.yaml");
  for (const TunedParameter& parameter : spec.parameters) {
    const std::string key = parameter.key.substr(0, parameter.key.find('['));
    fragment.Set(key, *document.Find(key));
  }
  return "# " + spec.name + ": tuned by trav tune (" + spec.source + ")\n" + fragment.Dump();
}

}  // namespace

TuneAlgorithm ParseTuneAlgorithm(const std::string& name) {
  const std::optional<TuneAlgorithm> algorithm = common::EnumFromName<TuneAlgorithm>(name);
  if (!algorithm) {
    throw common::InputError("--algorithm", name,
                             "expected one of: " + common::EnumNameList<TuneAlgorithm>());
  }
  return *algorithm;
}

TuneSpec LoadTuneFile(const std::string& path) {
  const common::YamlDocument document = common::YamlDocument::Load(path);
  common::YamlReader root = document.Root();
  TuneSpec spec;
  spec.source = path;
  RunFileHeader header = ReadRunFileHeader(&root, path);
  spec.name = std::move(header.name);
  spec.scenarios = std::move(header.scenarios);
  spec.sets = std::move(header.sets);
  spec.seeds = {"1"};
  root.Read("seeds", &spec.seeds);
  root.Check("seeds", !spec.seeds.empty() && spec.seeds.size() <= 1000,
             "must list 1 to 1000 seeds");
  root.Read("held_out_seeds", &spec.held_out_seeds);
  root.Check("held_out_seeds", spec.held_out_seeds.size() <= 1000, "must list at most 1000 seeds");
  common::YamlReader parameters = root.Map("parameters");
  for (const std::string& key : parameters.Keys()) {
    common::YamlReader range = parameters.Map(key);
    TunedParameter parameter;
    parameter.key = key;
    range.ReadRequired("min", &parameter.min);
    range.ReadRequired("max", &parameter.max);
    std::string scale = "linear";
    range.Read("scale", &scale);
    range.Check("scale", scale == "linear" || scale == "log", "must be linear or log");
    parameter.log = scale == "log";
    range.Read("integer", &parameter.integer);
    range.Check("max", parameter.max > parameter.min, "must be > min (an empty range)");
    range.Check("min", !parameter.log || parameter.min > 0.0, "must be > 0 on a log scale");
    range.Finish();
    spec.parameters.push_back(parameter);
  }
  parameters.Finish();
  root.Check("parameters", !spec.parameters.empty() && spec.parameters.size() <= 100,
             "must name 1 to 100 parameters");
  const std::set<std::string> known = KnownMetrics();
  common::YamlReader objective = root.Map("objective");
  for (const std::string& metric : objective.Keys()) {
    common::YamlReader term_reader = objective.Map(metric);
    ObjectiveTerm term;
    term.metric = metric;
    term_reader.Read("weight", &term.weight);
    if (term_reader.Has("target")) {
      double target = 0.0;
      term_reader.Read("target", &target);
      term.target = target;
    }
    term_reader.Finish();
    objective.Check(metric, known.count(metric) > 0,
                    "is not a summary.json metric (docs/tuning.md lists them)");
    spec.objective.push_back(term);
  }
  objective.Finish();
  root.Check("objective", !spec.objective.empty(), "must have at least one metric");
  root.Read("failure_penalty", &spec.failure_penalty);
  root.ReadEnum("algorithm", &spec.algorithm);
  root.Read("budget", &spec.budget);
  root.Check("budget", spec.budget >= 2 && spec.budget <= 100000, "must be in [2, 100000]");
  root.Read("seed", &spec.seed);
  root.Read("time_limit", &spec.time_limit_s);
  root.Check("time_limit", spec.time_limit_s > 0.0 && spec.time_limit_s <= 1e6,
             "must be in (0, 1e6] s");
  root.Finish();

  // every parameter is a number of every scenario
  for (const std::string& scenario : spec.scenarios) {
    const common::YamlDocument resolved = ResolvedDocument(spec, scenario, spec.seeds.front());
    for (const TunedParameter& parameter : spec.parameters) {
      const std::optional<std::string> value = resolved.Find(parameter.key);
      char* end = nullptr;
      if (!value || (std::strtod(value->c_str(), &end), *end != '\0') || value->empty()) {
        throw common::InputError(path, "parameters." + parameter.key,
                                 "is not a number in scenario " + scenario);
      }
    }
  }
  return spec;
}

namespace {

// The folder's identity: the tuning file it belongs to (a folder of another tuning is refused).
void ClaimTuneFolder(const TuneSpec& spec, const CampaignFolder& campaign) {
  const nlohmann::json identity = {{"source", spec.source}, {"tuning", ReadTextFile(spec.source)}};
  campaign.Claim(
      identity, [&](const nlohmann::json& previous) { return previous == identity; },
      "the folder holds another tuning; use another --out, or the same tuning file to resume it");
}

// The search: NLopt from the scenarios' own values over the unit cube of the parameters, every
// evaluation appended to evaluations.csv. Fills the result's initial and best values.
void Search(const TuneSpec& spec, const fs::path& folder, const TuneExecution& execution,
            TuneResult* result_out) {
  TuneResult& result = *result_out;
  // the scenarios' own values (of the first scenario) start the search
  const common::YamlDocument first =
      ResolvedDocument(spec, spec.scenarios.front(), spec.seeds.front());
  std::vector<double> start(spec.parameters.size());
  for (std::size_t i = 0; i < spec.parameters.size(); ++i) {
    result.initial.push_back(std::stod(*first.Find(spec.parameters[i].key)));
    start[i] = CoordinateOf(spec.parameters[i], result.initial[i]);
  }

  std::string csv = "evaluation,objective,best_objective,failures";
  for (const TunedParameter& p : spec.parameters) csv += "," + p.key + "," + p.key + "_u";
  csv += "\n";
  result.best_objective = std::numeric_limits<double>::infinity();
  nlopt::opt optimiser(NloptAlgorithm(spec.algorithm), static_cast<unsigned>(start.size()));
  nlopt::srand(spec.seed);
  optimiser.set_lower_bounds(0.0);
  optimiser.set_upper_bounds(1.0);
  optimiser.set_maxeval(spec.budget);
  optimiser.set_initial_step(0.2);
  optimiser.set_xtol_abs(1e-4);
  if (spec.algorithm == TuneAlgorithm::kCrs || spec.algorithm == TuneAlgorithm::kEsch) {
    optimiser.set_population(static_cast<unsigned>(std::max<std::size_t>(10, 5 * start.size())));
  }
  auto objective = [&](const std::vector<double>& u) {
    std::vector<double> values(u.size());
    for (std::size_t i = 0; i < u.size(); ++i) values[i] = ValueOf(spec.parameters[i], u[i]);
    const bool cached = fs::exists(folder / "candidates" / HashOf(values) / "parameters.json");
    const Evaluation evaluation = Evaluate(spec, values, spec.seeds, folder, execution);
    if (evaluation.interrupted) {
      result.interrupted = true;
      optimiser.force_stop();
      return std::numeric_limits<double>::max();
    }
    ++result.evaluations;
    result.cached += cached ? 1 : 0;
    if (result.evaluations == 1) result.initial_objective = evaluation.objective;
    if (evaluation.objective < result.best_objective || result.best.empty()) {
      result.best_objective = evaluation.objective;
      result.best = values;
    }
    csv += std::to_string(result.evaluations) + "," + Number(evaluation.objective) + "," +
           Number(result.best_objective) + "," + std::to_string(evaluation.failures);
    for (std::size_t i = 0; i < values.size(); ++i) {
      csv += "," + Number(values[i]) + "," + Number(CoordinateOf(spec.parameters[i], values[i]));
    }
    csv += "\n";
    WriteTextFileAtomically((folder / "evaluations.csv").string(), csv);
    common::Log(common::LogLevel::kInfo,
                fmt::format("evaluation {}/{}: objective {:.6g} (best {:.6g}){}",
                            result.evaluations, spec.budget, evaluation.objective,
                            result.best_objective, cached ? " [from the folder]" : ""));
    return evaluation.objective;
  };
  optimiser.set_min_objective(
      [](const std::vector<double>& u, std::vector<double>&, void* data) {
        return (*static_cast<decltype(objective)*>(data))(u);
      },
      &objective);
  double minimum = 0.0;
  try {
    optimiser.optimize(start, minimum);
  } catch (const nlopt::forced_stop&) {
  } catch (const nlopt::roundoff_limited&) {
  }
}

// The scenarios' values and the tuned ones, each on the training and the held-out seeds.
struct Comparison {
  Evaluation initial_training;
  Evaluation best_training;
  std::optional<Evaluation> initial_held_out;
  std::optional<Evaluation> best_held_out;
};

// objective.png and parameters.png from evaluations.csv.
PlotResult WriteTunePlots(const TuneSpec& spec, const fs::path& folder) {
  std::vector<PlotSeries> coordinates;
  for (const TunedParameter& p : spec.parameters) coordinates.push_back({p.key + "_u", p.key});
  const std::vector<LinePlot> plots = {
      {"objective.png",
       "Objective over evaluations",
       "evaluation",
       "evaluation",
       "objective",
       {{"objective", "objective"}, {"best_objective", "best so far"}},
       false,
       true},
      {"parameters.png", "Parameters over evaluations (0 = min, 1 = max of each range)",
       "evaluation", "evaluation", "position in its range", coordinates, true, true}};
  const PlotResult plotted =
      WriteLinePlots((folder / "evaluations.csv").string(), plots, folder.string());

  return plotted;
}

// report.md: the objective, the comparison on training and held-out seeds, the values.
std::string TuneReport(const TuneSpec& spec, const TuneResult& result, const Comparison& c,
                       const PlotResult& plotted) {
  const Evaluation& initial_training = c.initial_training;
  const Evaluation& best_training = c.best_training;
  const std::optional<Evaluation>& initial_held_out = c.initial_held_out;
  const std::optional<Evaluation>& best_held_out = c.best_held_out;
  const char* algorithm_name = common::NameOf(spec.algorithm);
  auto join = [](const std::vector<std::string>& items) {
    std::string text;
    for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
    return text;
  };
  std::ostringstream md;
  md << "# Tuning " << spec.name << "\n\n"
     << "Tuning file `" << spec.source << "`: NLopt " << algorithm_name << ", "
     << result.evaluations << " evaluations (" << result.cached << " found in the folder), each on "
     << spec.scenarios.size() << " scenarios x " << spec.seeds.size() << " training seeds ("
     << join(spec.seeds) << "); held-out seeds: "
     << (spec.held_out_seeds.empty() ? std::string("none") : join(spec.held_out_seeds))
     << ".\n\nObjective: the mean over runs of ";
  for (const ObjectiveTerm& term : spec.objective) {
    md << (&term == &spec.objective.front() ? "" : " + ") << Number(term.weight) << " x "
       << (term.target ? "|" + term.metric + " - " + Number(*term.target) + "|" : term.metric);
  }
  md << ", plus " << Number(spec.failure_penalty)
     << " per run that does not end as its scenario expects.\n\n| | training objective | held-out "
        "objective | failed runs (training / held-out) |";
  for (const ObjectiveTerm& term : spec.objective) {
    md << " " << term.metric << " (training / held-out) |";
  }
  md << "\n|---|---|---|---|";
  for (std::size_t i = 0; i < spec.objective.size(); ++i) md << "---|";
  md << "\n";
  auto row = [&](const char* label, const Evaluation& training,
                 const std::optional<Evaluation>& held_out) {
    md << "| " << label << " | " << common::FormatNumber("%.6g", training.objective) << " | "
       << (held_out ? common::FormatNumber("%.6g", held_out->objective) : std::string("-")) << " | "
       << training.failures << " / " << (held_out ? std::to_string(held_out->failures) : "-")
       << " |";
    for (const ObjectiveTerm& term : spec.objective) {
      auto mean = [&](const Evaluation& e) {
        const auto it = e.metric_means.find(term.metric);
        return it == e.metric_means.end() ? std::string("-")
                                          : common::FormatNumber("%.4g", it->second);
      };
      md << " " << mean(training) << " / " << (held_out ? mean(*held_out) : std::string("-"))
         << " |";
    }
    md << "\n";
  };
  row("scenario values", initial_training, initial_held_out);
  row("tuned", best_training, best_held_out);
  const double reference =
      initial_held_out ? initial_held_out->objective : initial_training.objective;
  const double tuned = best_held_out ? best_held_out->objective : best_training.objective;
  const char* where = initial_held_out ? "held-out" : "training";
  md << "\n";
  if (tuned < reference) {
    md << "The tuned values lower the " << where << " objective by "
       << common::FormatNumber("%.1f", 100.0 * (reference - tuned) / reference) << " % (training: "
       << common::FormatNumber("%.1f", 100.0 *
                                           (initial_training.objective - best_training.objective) /
                                           initial_training.objective)
       << " %).\n";
  } else {
    md << "Tuning could not improve the " << where << " objective ("
       << common::FormatNumber("%.6g", reference) << " with the scenarios' values, "
       << common::FormatNumber("%.6g", tuned) << " tuned): keep the scenarios' values.\n";
  }
  md << "\n## Parameters\n\n| parameter | range | scenario value | tuned |\n|---|---|---|---|\n";
  for (std::size_t i = 0; i < spec.parameters.size(); ++i) {
    const TunedParameter& p = spec.parameters[i];
    md << "| " << p.key << " | [" << Number(p.min) << ", " << Number(p.max) << "]"
       << (p.log ? " log" : "") << (p.integer ? " integer" : "") << " | "
       << Number(result.initial[i]) << " | " << Number(result.best[i]) << " |\n";
  }
  md << "\n`tuned.yaml`, to paste into a scenario:\n\n```yaml\n"
     << TunedYaml(spec, result.best) << "```\n\n";
  for (const std::string& image : plotted.written) md << "![" << image << "](" << image << ")\n";
  if (!plotted.message.empty()) md << "\n" << plotted.message << "\n";
  return md.str();
}

}  // namespace

TuneResult RunTuning(const TuneSpec& spec, const std::string& out_dir,
                     const TuneExecution& execution) {
  if (execution.slurm) ValidateSlurmOptions(*execution.slurm);
  const CampaignFolder campaign(out_dir, "tune", "tune.json", {});
  const fs::path folder = fs::absolute(out_dir);
  fs::create_directories(folder / "candidates");
  ClaimTuneFolder(spec, campaign);
  TuneResult result;
  Search(spec, folder, execution, &result);
  if (result.interrupted) return result;

  // the initial and the best values on the training and the held-out seeds
  Comparison comparison{Evaluate(spec, result.initial, spec.seeds, folder, execution),
                        Evaluate(spec, result.best, spec.seeds, folder, execution), std::nullopt,
                        std::nullopt};
  if (!spec.held_out_seeds.empty()) {
    comparison.initial_held_out =
        Evaluate(spec, result.initial, spec.held_out_seeds, folder, execution);
    comparison.best_held_out = Evaluate(spec, result.best, spec.held_out_seeds, folder, execution);
    if (comparison.initial_held_out->interrupted || comparison.best_held_out->interrupted) {
      result.interrupted = true;
      return result;
    }
    result.initial_held_out = comparison.initial_held_out->objective;
    result.best_held_out = comparison.best_held_out->objective;
  }

  WriteTextFileAtomically((folder / "tuned.yaml").string(), TunedYaml(spec, result.best));
  const PlotResult plotted = WriteTunePlots(spec, folder);
  WriteTextFileAtomically((folder / "report.md").string(),
                          TuneReport(spec, result, comparison, plotted));
  return result;
}

}  // namespace trav::scenarios
