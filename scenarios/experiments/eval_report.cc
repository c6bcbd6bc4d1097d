#include "scenarios/experiments/eval_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/statistics.h"
#include "common/text.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/plots.h"
#include "scenarios/run/run_metrics.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

// The paper's Table I (average mean error / average variance).
struct PaperRow {
  const char* terrain;
  double sgp[2];
  double fsgp[2];
  double fsgp_bgk[2];
};
constexpr PaperRow kPaperTableI[] = {
    {"hilly", {0.2604, 0.0392}, {0.2321, 0.0345}, {0.1237, 0.0085}},
    {"forest", {0.1831, 0.0245}, {0.1777, 0.0227}, {0.1687, 0.0213}},
    {"ruin", {0.2003, 0.0239}, {0.1965, 0.0219}, {0.1831, 0.0206}},
    {"road", {0.1694, 0.0373}, {0.1434, 0.0328}, {0.1051, 0.0240}},
    {"indoor", {0.2455, 0.0451}, {0.2537, 0.0429}, {0.1978, 0.0420}},
};

// A method's record in a scene, or null.
const EvalMethodRecord* MethodRecord(const EvalSceneRecord& scene, const std::string& method) {
  const auto it = scene.methods.find(method);
  return it == scene.methods.end() ? nullptr : &it->second;
}

// An aggregate over every terrain type (Tables II and III), computed like a row.
std::optional<EvalAggregate> OverAllTerrains(const std::vector<EvalSceneRecord>& scenes,
                                             const std::string& method) {
  std::vector<EvalSceneRecord> relabelled = scenes;
  for (EvalSceneRecord& scene : relabelled) scene.terrain = "all";
  const std::vector<EvalAggregate> rows = AggregateScenes(relabelled, {"all"}, {method});
  if (rows.empty()) return std::nullopt;
  return rows.front();
}

// error_over_time_<terrain>.csv: t and one column per method, each the mean over the type's
// scenes of the frame's mean error (frames are indexed alike in every scene: one per LiDAR
// period); empty fields where no scene scored that frame.
std::string ErrorOverTimeCsv(const std::vector<EvalSceneRecord>& scenes, const std::string& terrain,
                             const std::vector<std::string>& methods) {
  std::size_t frames = 0;
  std::vector<const EvalSceneRecord*> of_type;
  for (const EvalSceneRecord& scene : scenes) {
    if (scene.terrain != terrain) continue;
    of_type.push_back(&scene);
    frames = std::max(frames, scene.drive.frames);
  }
  std::string csv = "t";
  for (const std::string& method : methods) csv += "," + method;
  for (const std::string& method : methods) csv += "," + method + "_min," + method + "_max";
  csv += "\n";
  for (std::size_t k = 0; k < frames; ++k) {
    double t_sum = 0.0;
    int t_count = 0;
    std::string row, ranges;
    for (const std::string& method : methods) {
      double sum = 0.0, low = 0.0, high = 0.0;
      int count = 0;
      for (const EvalSceneRecord* scene : of_type) {
        const EvalMethodRecord* record = MethodRecord(*scene, method);
        if (record == nullptr) continue;
        const EvalFrames& per_frame = record->frames;
        if (k >= per_frame.t_s.size()) continue;
        if (method == methods.front()) {
          t_sum += per_frame.t_s[k];
          ++t_count;
        }
        if (k < per_frame.mean_error.size() && per_frame.mean_error[k]) {
          const double error = *per_frame.mean_error[k];
          low = count == 0 ? error : std::min(low, error);
          high = count == 0 ? error : std::max(high, error);
          sum += error;
          ++count;
        }
      }
      const auto number = [count](double value) {
        return count > 0 ? common::FormatNumber("%.6g", value) : std::string();
      };
      row += "," + number(sum / std::max(count, 1));
      ranges += "," + number(low) + "," + number(high);
    }
    if (t_count == 0) continue;
    csv += common::FormatNumber("%.3f", t_sum / t_count) + row + ranges + "\n";
  }
  return csv;
}

// One row of the inducing-point ablation: a GP mapper at a count, and the method that ran it (the
// mapper itself at the scenes' own count).
struct AblationRow {
  std::string base;
  int inducing_points;
  std::string method;
};

// The ablation's rows: each ablated GP mapper at every count, in ascending order.
std::vector<AblationRow> AblationRows(const EvalOptions& options, int base_inducing_points) {
  std::vector<int> counts = options.inducing_points;
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
  std::vector<AblationRow> rows;
  for (const std::string& base : AblatedMethods(options)) {
    for (const int count : counts) {
      rows.push_back(
          {base, count, count == base_inducing_points ? base : AblationMethod{base, count}.Name()});
    }
  }
  return rows;
}

const EvalAggregate* Find(const std::vector<EvalAggregate>& rows, const std::string& terrain,
                          const std::string& method) {
  for (const EvalAggregate& row : rows) {
    if (row.terrain == terrain && row.method == method) return &row;
  }
  return nullptr;
}

void WriteCsvAndPlots(const fs::path& folder, const std::string& csv_name, const std::string& csv,
                      const std::vector<LinePlot>& plots, std::vector<std::string>* notes) {
  WriteTextFileAtomically((folder / csv_name).string(), csv);
  const PlotResult result = WriteLinePlots((folder / csv_name).string(), plots, folder.string());
  if (!result.message.empty()) notes->push_back(result.message);
}

// A terrain-by-method table: a row per terrain type, a column per method, each cell `cell` of the
// method's aggregate ("-" where it has none on that terrain).
std::string TerrainByMethodTable(const std::vector<EvalAggregate>& rows,
                                 const std::vector<std::string>& terrains,
                                 const std::vector<std::string>& methods,
                                 const std::function<std::string(const EvalAggregate&)>& cell) {
  std::ostringstream md;
  md << "| terrain |";
  for (const std::string& method : methods) md << " " << method << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < methods.size(); ++i) md << "---|";
  md << "\n";
  for (const std::string& terrain : terrains) {
    md << "| " << terrain << " |";
    for (const std::string& method : methods) {
      const EvalAggregate* row = Find(rows, terrain, method);
      md << " " << (row ? cell(*row) : std::string("-")) << " |";
    }
    md << "\n";
  }
  return md.str();
}

std::string TableOne(const std::vector<EvalAggregate>& rows, const EvalOptions& options,
                     const std::vector<std::string>& methods) {
  std::ostringstream md;
  md << "## Table I: mean error / error variance per terrain type\n\n"
     << "Mean over scenes of the per-frame mean |traversability - ground truth| over the cells "
        "observed so far, and of its variance.\n\n"
     << TerrainByMethodTable(rows, options.terrains, methods, [](const EvalAggregate& row) {
          return common::FormatNumber("%.4f", row.mean_error) + " / " +
                 common::FormatNumber("%.4f", row.error_variance);
        });
  md << "\nThe paper's Table I (its simulator, its ground-truth formula):\n\n"
     << "| terrain | sgp | fsgp | fsgp-bgk |\n|---|---|---|---|\n";
  for (const PaperRow& paper : kPaperTableI) {
    md << "| " << paper.terrain << " | " << common::FormatNumber("%.4f", paper.sgp[0]) << " / "
       << common::FormatNumber("%.4f", paper.sgp[1]) << " | "
       << common::FormatNumber("%.4f", paper.fsgp[0]) << " / "
       << common::FormatNumber("%.4f", paper.fsgp[1]) << " | "
       << common::FormatNumber("%.4f", paper.fsgp_bgk[0]) << " / "
       << common::FormatNumber("%.4f", paper.fsgp_bgk[1]) << " |\n";
  }
  return md.str();
}

// Which ground truth the maps were scored against, and what is untraversable in it.
std::string TruthNote(const EvalOptions& options) {
  if (options.truth == "physical") {
    return "Ground truth: **physical** (docs/ground-truth.md): the Scout Mini resting on the dense "
           "world at 16 headings, its pitch, roll, wheel steps and belly clearance against its "
           "measured limits; a cell's cost is the largest normalised violation at its best "
           "heading, and it is untraversable (cost 1) where no heading is within every limit.";
  }
  return "Ground truth: **geometric** (docs/ground-truth.md): the mappers' score formula on the "
         "exact heights; untraversable where its cost is at or above the planner's lethal "
         "threshold.";
}

// A metric's value for a table cell ("-" when unset).
std::string Cell(const std::optional<double>& value, const char* format) {
  return value ? common::FormatNumber(format, *value) : std::string("-");
}

// The hazard table: AUROC, average precision, Spearman and calibrated error per terrain and method.
std::string HazardTable(const std::vector<EvalAggregate>& rows, const EvalOptions& options,
                        const std::vector<std::string>& methods) {
  std::ostringstream md;
  md << "## Finding hazards: AUROC / average precision / Spearman / calibrated error\n\n"
     << "On the final map of each scene over its observed cells (docs/evaluation.md): how the cost "
        "ranks the untraversable cells (see the ground truth above), its rank "
        "correlation with the truth's cost, and the mean error after a monotone calibration fitted "
        "on the method's other scenes; means over scenes. A constant map has AUROC 0.5, the "
        "oracle 1.\n\n"
     << TerrainByMethodTable(rows, options.terrains, methods, [](const EvalAggregate& row) {
          return Cell(row.auroc, "%.3f") + " / " + Cell(row.average_precision, "%.3f") + " / " +
                 Cell(row.spearman, "%.3f") + " / " + Cell(row.calibrated_mae, "%.4f");
        });
  return md.str();
}

// The paired differences against the reference, with the claims they settle.
std::string PairedTable(const std::vector<EvalAggregate>& rows) {
  std::ostringstream md;
  md << "## Paired differences (95 % bootstrap intervals over scenes)\n\n"
     << "Each method minus the reference on the same scenes; a claim is made only where the "
        "interval excludes zero over at least 5 scenes.\n\n| terrain | method | metric | scenes | "
        "difference | interval | "
        "claim |\n|---|---|---|---|---|---|---|\n";
  for (const EvalAggregate& row : rows) {
    for (const PairedDifference& d : row.paired) {
      const std::string unsettled =
          d.scenes < 5 ? "not settled (fewer than 5 scenes)" : "not settled";
      const std::string claim = d.verdict == "not settled"
                                    ? unsettled
                                    : row.paired_with +
                                          (d.verdict == "worse" ? " beats " : " loses to ") +
                                          row.method + " in " + d.metric + " on " + row.terrain;
      md << "| " << row.terrain << " | " << row.method << " vs " << row.paired_with << " | "
         << d.metric << " | " << d.scenes << " | " << common::FormatNumber("%+.4f", d.mean)
         << " | [" << common::FormatNumber("%+.4f", d.low) << ", "
         << common::FormatNumber("%+.4f", d.high) << "] | " << claim << " |\n";
    }
  }
  return md.str();
}

// A two-method comparison over every terrain type (Tables II and III).
std::string Comparison(const std::vector<EvalSceneRecord>& scenes, const std::string& title,
                       const std::vector<std::pair<std::string, std::string>>& methods_and_paper,
                       const std::string& paper_header) {
  std::ostringstream md;
  md << "## " << title << "\n\n| method | mean error | error variance | median update [ms] | "
     << "peak memory [MiB] | " << paper_header << " |\n|---|---|---|---|---|---|\n";
  for (const auto& [method, paper] : methods_and_paper) {
    const std::optional<EvalAggregate> row = OverAllTerrains(scenes, method);
    if (!row) {
      md << "| " << method << " | not evaluated (add it to --methods) | | | | " << paper << " |\n";
      continue;
    }
    md << "| " << method << " | " << common::FormatNumber("%.4f", row->mean_error) << " | "
       << common::FormatNumber("%.4f", row->error_variance) << " | "
       << common::FormatNumber("%.2f", row->runtime_ms_median) << " | "
       << common::FormatNumber("%.2f", row->peak_memory_mb) << " | " << paper << " |\n";
  }
  return md.str();
}

// "Drives ...: success 9, planning_failure 1 (indoor-2)." from the scenes' drive outcomes.
std::string DriveOutcomes(const std::vector<EvalSceneRecord>& scenes) {
  std::map<std::string, std::vector<std::string>> by_outcome;
  for (const EvalSceneRecord& scene : scenes) by_outcome[scene.drive.outcome].push_back(scene.id);
  std::string text =
      "Drives (the closed loop on the ground-truth oracle; every frame until the "
      "drive ends is scored):";
  bool first = true;
  for (const auto& [outcome, ids] : by_outcome) {
    text += std::string(first ? " " : ", ") + outcome + " " + std::to_string(ids.size());
    first = false;
    if (outcome == "success" || outcome == "completed") continue;
    std::string list;
    for (const std::string& id : ids) list += (list.empty() ? "" : ", ") + id;
    text += " (" + list + ")";
  }
  return text + ".";
}

}  // namespace

void to_json(nlohmann::json& json, const EvalAggregate& row) {
  json = {{"terrain", row.terrain},
          {"method", row.method},
          {"mean_error", row.mean_error},
          {"error_variance", row.error_variance},
          {"runtime_ms_median", row.runtime_ms_median},
          {"peak_memory_mb", row.peak_memory_mb},
          {"scenes", row.scenes},
          {"frames", row.frames},
          {"coverage", row.coverage},
          {"cpu_ms_median", row.runtime_ms_median},
          {"wall_ms_median", row.wall_ms_median},
          {"auroc", NumberOrNull(row.auroc)},
          {"average_precision", NumberOrNull(row.average_precision)},
          {"spearman", NumberOrNull(row.spearman)},
          {"calibrated_mae", NumberOrNull(row.calibrated_mae)},
          {"elevation_rmse", NumberOrNull(row.elevation_rmse)},
          {"scene_values", row.scene_values},
          {"paired_with", row.paired_with},
          {"paired", row.paired}};
}

void from_json(const nlohmann::json& json, EvalAggregate& row) {
  json.at("terrain").get_to(row.terrain);
  json.at("method").get_to(row.method);
  json.at("mean_error").get_to(row.mean_error);
  json.at("error_variance").get_to(row.error_variance);
  json.at("runtime_ms_median").get_to(row.runtime_ms_median);
  json.at("peak_memory_mb").get_to(row.peak_memory_mb);
  json.at("scenes").get_to(row.scenes);
  json.at("frames").get_to(row.frames);
  json.at("coverage").get_to(row.coverage);
  json.at("wall_ms_median").get_to(row.wall_ms_median);
  row.auroc = OptionalNumber(json.at("auroc"));
  row.average_precision = OptionalNumber(json.at("average_precision"));
  row.spearman = OptionalNumber(json.at("spearman"));
  row.calibrated_mae = OptionalNumber(json.at("calibrated_mae"));
  row.elevation_rmse = OptionalNumber(json.at("elevation_rmse"));
  json.at("scene_values").get_to(row.scene_values);
  json.at("paired_with").get_to(row.paired_with);
  json.at("paired").get_to(row.paired);
}

namespace {

// The mean of a metric over the scenes where it is defined.
std::optional<double> MeanOver(const std::vector<SceneMetrics>& scenes, const std::string& metric) {
  double sum = 0.0;
  int count = 0;
  for (const SceneMetrics& scene : scenes) {
    if (const std::optional<double> value = MetricOf(scene, metric)) {
      sum += *value;
      ++count;
    }
  }
  return count > 0 ? std::optional<double>(sum / count) : std::nullopt;
}

// The hazard metrics of a row from its scenes' values, and the differences against `reference`.
void AddHazardMetrics(const std::vector<SceneMetrics>& of_type,
                      const std::vector<SceneMetrics>& reference_of_type,
                      const std::string& reference, EvalAggregate* row) {
  row->scene_values = of_type;
  row->auroc = MeanOver(of_type, "auroc");
  row->average_precision = MeanOver(of_type, "average_precision");
  row->spearman = MeanOver(of_type, "spearman");
  row->calibrated_mae = MeanOver(of_type, "calibrated_mae");
  row->elevation_rmse = MeanOver(of_type, "elevation_rmse");
  if (row->method == reference || reference_of_type.empty()) return;
  row->paired_with = reference;
  row->paired = PairedDifferences(of_type, reference_of_type);
}

// The metrics of the scenes of one terrain type.
std::vector<SceneMetrics> OfTerrain(const std::vector<SceneMetrics>& metrics,
                                    const std::vector<EvalSceneRecord>& scenes,
                                    const std::string& terrain) {
  std::vector<SceneMetrics> of_type;
  for (const SceneMetrics& m : metrics) {
    for (const EvalSceneRecord& scene : scenes) {
      if (scene.id == m.id && scene.terrain == terrain) of_type.push_back(m);
    }
  }
  return of_type;
}

}  // namespace

std::vector<EvalAggregate> AggregateScenes(const std::vector<EvalSceneRecord>& scenes,
                                           const std::vector<std::string>& terrains,
                                           const std::vector<std::string>& methods,
                                           const std::string& reference) {
  std::map<std::string, std::vector<SceneMetrics>> metrics;
  for (const std::string& method : methods) metrics[method] = MethodSceneMetrics(scenes, method);
  const std::vector<SceneMetrics> none;
  const auto reference_metrics = metrics.find(reference);
  std::vector<EvalAggregate> rows;
  for (const std::string& terrain : terrains) {
    for (const std::string& method : methods) {
      EvalAggregate row;
      row.terrain = terrain;
      row.method = method;
      std::vector<double> runtimes, walls;
      for (const EvalSceneRecord& scene : scenes) {
        if (scene.terrain != terrain) continue;
        const EvalMethodRecord* record = MethodRecord(scene, method);
        if (record == nullptr || !record->mean_error) continue;
        ++row.scenes;
        row.mean_error += *record->mean_error;
        row.error_variance += record->error_variance.value();
        row.coverage += record->coverage;
        row.peak_memory_mb = std::max(row.peak_memory_mb, record->peak_memory_mb);
        runtimes.insert(runtimes.end(), record->frames.runtime_ms.begin(),
                        record->frames.runtime_ms.end());
        walls.insert(walls.end(), record->frames.wall_ms.begin(), record->frames.wall_ms.end());
      }
      if (row.scenes == 0) continue;
      row.mean_error /= row.scenes;
      row.error_variance /= row.scenes;
      row.coverage /= row.scenes;
      row.frames = static_cast<int>(runtimes.size());
      row.runtime_ms_median = common::Quantile(runtimes, 0.5);
      row.wall_ms_median = common::Quantile(walls, 0.5);
      AddHazardMetrics(OfTerrain(metrics[method], scenes, terrain),
                       reference_metrics == metrics.end()
                           ? none
                           : OfTerrain(reference_metrics->second, scenes, terrain),
                       reference, &row);
      rows.push_back(row);
    }
  }
  return rows;
}

namespace {

// results.json and results.csv: one row per terrain type and method.
void WriteEvalResults(const fs::path& folder, const std::vector<EvalAggregate>& rows) {
  std::string csv =
      "terrain,method,mean_error,error_variance,runtime_ms_median,peak_memory_mb,scenes,frames,"
      "coverage,cpu_ms_median,wall_ms_median,auroc,average_precision,spearman,calibrated_mae,"
      "elevation_rmse\n";
  auto optional = [](const std::optional<double>& value) {
    return value ? common::FormatNumber("%.6g", *value) : std::string();
  };
  for (const EvalAggregate& row : rows) {
    csv += row.terrain + "," + row.method + "," + common::FormatNumber("%.6g", row.mean_error) +
           "," + common::FormatNumber("%.6g", row.error_variance) + "," +
           common::FormatNumber("%.6g", row.runtime_ms_median) + "," +
           common::FormatNumber("%.6g", row.peak_memory_mb) + "," + std::to_string(row.scenes) +
           "," + std::to_string(row.frames) + "," + common::FormatNumber("%.4f", row.coverage) +
           "," + common::FormatNumber("%.6g", row.runtime_ms_median) + "," +
           common::FormatNumber("%.6g", row.wall_ms_median) + "," + optional(row.auroc) + "," +
           optional(row.average_precision) + "," + optional(row.spearman) + "," +
           optional(row.calibrated_mae) + "," + optional(row.elevation_rmse) + "\n";
  }
  WriteTextFileAtomically((folder / "results.json").string(), nlohmann::json(rows).dump(1) + "\n");
  WriteTextFileAtomically((folder / "results.csv").string(), csv);
}

// The error-over-time CSV and plot of each terrain type (notes on missing plots to `notes`).
void WriteErrorOverTime(const fs::path& folder, const EvalOptions& options,
                        const std::vector<EvalSceneRecord>& scenes,
                        std::vector<std::string>* notes) {
  std::vector<PlotSeries> method_series;
  for (const std::string& method : options.methods) {
    method_series.push_back(
        {method, method, method + "_min", method + "_max", method + ", range over scenes"});
  }
  for (const std::string& terrain : options.terrains) {
    const LinePlot plot{"error_over_time_" + terrain + ".png",
                        "Mapping error over time, " + terrain + " (mean and range over scenes)",
                        "t",
                        "simulation time [s]",
                        "mean |traversability - ground truth|",
                        method_series,
                        true,
                        false};
    WriteCsvAndPlots(folder, "error_over_time_" + terrain + ".csv",
                     ErrorOverTimeCsv(scenes, terrain, options.methods), {plot}, notes);
  }
}

// FSGP-BGK's rows of the ablation: ablation.csv and its plots (error and update time against M).
void WriteFsgpBgkAblation(const fs::path& folder, const EvalOptions& options,
                          const std::vector<EvalAggregate>& rows,
                          const std::vector<AblationRow>& ablation,
                          std::vector<std::string>* notes) {
  std::string ablation_csv = "inducing_points";
  std::vector<PlotSeries> error_series, runtime_series;
  for (const std::string& terrain : options.terrains) {
    ablation_csv += "," + terrain + "_error," + terrain + "_runtime_ms";
    error_series.push_back({terrain + "_error", terrain});
    runtime_series.push_back({terrain + "_runtime_ms", terrain});
  }
  ablation_csv += "\n";
  for (const AblationRow& ablated : ablation) {
    if (ablated.base != "fsgp-bgk") continue;
    ablation_csv += std::to_string(ablated.inducing_points);
    for (const std::string& terrain : options.terrains) {
      const EvalAggregate* row = Find(rows, terrain, ablated.method);
      ablation_csv += row ? "," + common::FormatNumber("%.6g", row->mean_error) + "," +
                                common::FormatNumber("%.6g", row->runtime_ms_median)
                          : std::string(",,");
    }
    ablation_csv += "\n";
  }
  const std::vector<LinePlot> plots = {
      {"ablation_error.png", "FSGP-BGK: mean error against inducing points", "inducing_points",
       "inducing points M", "mean |traversability - ground truth|", error_series, true, true},
      {"ablation_runtime.png", "FSGP-BGK: median update against inducing points", "inducing_points",
       "inducing points M", "median update [ms]", runtime_series, true, true}};
  WriteCsvAndPlots(folder, "ablation.csv", ablation_csv, plots, notes);
}

// The inducing-point ablation of every ablated GP mapper (the paper's: SGP, FSGP and FSGP-BGK at
// each M): ablation_methods.csv, FSGP-BGK's ablation.csv and plots, and the table for results.md
// (empty when there is no ablation).
std::string WriteAblation(const fs::path& folder, const EvalOptions& options,
                          const std::vector<EvalAggregate>& rows,
                          const std::vector<AblationRow>& ablation,
                          std::vector<std::string>* notes) {
  if (ablation.empty()) return "";
  auto optional_number = [](const char* format, const std::optional<double>& value) {
    return value ? common::FormatNumber(format, *value) : std::string();
  };
  std::string csv = "method,inducing_points";
  std::ostringstream md;
  md << "## Inducing-point ablation (the paper's: each GP mapper at each M)\n\n"
     << "Mean error / AUROC / median update [ms] (CPU).\n\n| method | inducing points |";
  for (const std::string& terrain : options.terrains) {
    csv += "," + terrain + "_error," + terrain + "_auroc," + terrain + "_average_precision," +
           terrain + "_runtime_ms";
    md << " " << terrain << " |";
  }
  csv += "\n";
  md << "\n|---|---|";
  for (std::size_t i = 0; i < options.terrains.size(); ++i) md << "---|";
  md << "\n";
  for (const AblationRow& ablated : ablation) {
    csv += ablated.base + "," + std::to_string(ablated.inducing_points);
    md << "| " << ablated.base << " | " << ablated.inducing_points << " |";
    for (const std::string& terrain : options.terrains) {
      const EvalAggregate* row = Find(rows, terrain, ablated.method);
      if (row == nullptr) {
        csv += ",,,,";
        md << " - |";
        continue;
      }
      csv += "," + common::FormatNumber("%.6g", row->mean_error) + "," +
             optional_number("%.6g", row->auroc) + "," +
             optional_number("%.6g", row->average_precision) + "," +
             common::FormatNumber("%.6g", row->runtime_ms_median);
      md << " " << common::FormatNumber("%.4f", row->mean_error) << " / "
         << Cell(row->auroc, "%.3f") << " / "
         << common::FormatNumber("%.2f", row->runtime_ms_median) << " |";
    }
    csv += "\n";
    md << "\n";
  }
  WriteTextFileAtomically((folder / "ablation_methods.csv").string(), csv);
  if (std::any_of(ablation.begin(), ablation.end(),
                  [](const AblationRow& row) { return row.base == "fsgp-bgk"; })) {
    WriteFsgpBgkAblation(folder, options, rows, ablation, notes);
    md << "\n![ablation](ablation_error.png)\n![ablation](ablation_runtime.png)\n";
  }
  return md.str();
}

// The mappers on each pose source against the true pose: pose_sources.csv and the table for
// results.md (empty without pose sources).
std::string WritePoseSources(const fs::path& folder, const EvalOptions& options,
                             const std::vector<EvalAggregate>& rows) {
  if (options.pose_sources.empty()) return "";
  std::string csv = "method,pose_source";
  std::ostringstream md;
  md << "## The mappers on another pose source\n\n"
     << "Each mapper fed the same drive's frames in the odometry frame of the pose source's "
        "estimate (docs/localization.md), scored against the truth in the world: mean error on the "
        "true pose -> on the source (change), and AUROC on the true pose -> on the source.\n\n"
     << "| method | pose source |";
  for (const std::string& terrain : options.terrains) {
    csv += "," + terrain + "_error_true," + terrain + "_error," + terrain + "_auroc_true," +
           terrain + "_auroc";
    md << " " << terrain << " |";
  }
  csv += "\n";
  md << "\n|---|---|";
  for (std::size_t i = 0; i < options.terrains.size(); ++i) md << "---|";
  md << "\n";
  auto number = [](const char* format, const std::optional<double>& value) {
    return value ? common::FormatNumber(format, *value) : std::string();
  };
  for (const std::string& source : options.pose_sources) {
    for (const std::string& mapper : PoseSourceMappers(options)) {
      csv += mapper + "," + source;
      md << "| " << mapper << " | " << source << " |";
      for (const std::string& terrain : options.terrains) {
        const EvalAggregate* on_true = Find(rows, terrain, mapper);
        const EvalAggregate* on_source =
            Find(rows, terrain, PoseSourceMethod{mapper, source}.Name());
        if (on_true == nullptr || on_source == nullptr) {
          csv += ",,,,";
          md << " - |";
          continue;
        }
        csv += "," + common::FormatNumber("%.6g", on_true->mean_error) + "," +
               common::FormatNumber("%.6g", on_source->mean_error) + "," +
               number("%.6g", on_true->auroc) + "," + number("%.6g", on_source->auroc);
        const double change = 100.0 * (on_source->mean_error / on_true->mean_error - 1.0);
        md << " " << common::FormatNumber("%.4f", on_true->mean_error) << " -> "
           << common::FormatNumber("%.4f", on_source->mean_error) << " ("
           << common::FormatNumber("%+.1f", change) << " %); " << Cell(on_true->auroc, "%.3f")
           << " -> " << Cell(on_source->auroc, "%.3f") << " |";
      }
      csv += "\n";
      md << "\n";
    }
  }
  WriteTextFileAtomically((folder / "pose_sources.csv").string(), csv);
  return md.str();
}

}  // namespace

void WriteEvalReport(const std::string& out_dir, const EvalOptions& options,
                     int base_inducing_points, const std::vector<EvalSceneRecord>& scenes,
                     const std::vector<nlohmann::json>& failures, const std::string& command) {
  const fs::path folder(out_dir);
  const std::vector<std::string> methods = EvalMethods(options);
  const std::vector<EvalAggregate> rows = AggregateScenes(scenes, options.terrains, methods);

  WriteEvalResults(folder, rows);

  // error over time per terrain type
  std::vector<std::string> notes;
  WriteErrorOverTime(folder, options, scenes, &notes);

  // the inducing-point ablation
  const std::vector<AblationRow> ablation = AblationRows(options, base_inducing_points);
  const std::string ablation_md = WriteAblation(folder, options, rows, ablation, &notes);
  const std::string pose_sources_md = WritePoseSources(folder, options, rows);

  // results.md
  std::ostringstream md;
  md << "# trav eval results\n\n"
     << "Command: `" << command << "`\n\n"
     << scenes.size() << " scenes finished";
  if (!failures.empty()) md << ", " << failures.size() << " failed";
  md << " (" << options.scenes << " per terrain type, seeds " << options.seed << " to "
     << options.seed + static_cast<std::uint64_t>(options.scenes) - 1
     << "); per-frame numbers in scenes/<id>.json. " << DriveOutcomes(scenes) << "\n\n"
     << TruthNote(options) << "\n\n"
     << TableOne(rows, options, methods) << "\n"
     << HazardTable(rows, options, methods) << "\n"
     << PairedTable(rows) << "\n"
     << Comparison(
            scenes, "Table II: FSGP-BGK against the elevation map (all terrain types)",
            {{"fsgp-bgk", "0.1139 / 0.0333 / 33.84 ms"}, {"em", "0.1953 / 0.0422 / 107.85 ms"}},
            "paper: error / variance / time (GPU)")
     << "\n"
     << Comparison(scenes, "Table III: BGK fusion against cloud accumulation (all terrain types)",
                   {{"fsgp-bgk", "GPU memory 25 %, 29.16 ms"},
                    {"fsgp-accumulation", "GPU memory 36 %, 42.37 ms"}},
                   "paper")
     << "\nPeak memory: the largest growth of the heap in use (glibc mallinfo2, all arenas) "
        "between the method's construction and the end of any of its updates in one scene.\n\n"
     << ablation_md << (pose_sources_md.empty() ? "" : "\n") << pose_sources_md;
  if (!failures.empty()) {
    md << "\n## Failed scenes\n\n| scene | end | exit code | signal | log "
          "|\n|---|---|---|---|---|\n";
    for (const nlohmann::json& failure : failures) {
      md << "| " << failure.value("id", "") << " | " << failure.value("end", "") << " | "
         << failure.value("exit_code", 0) << " | " << failure.value("signal", 0) << " | "
         << failure.value("log", "") << " |\n";
    }
  }
  md << "\n## Plots\n\n";
  for (const std::string& terrain : options.terrains) {
    md << "![" << terrain << "](error_over_time_" << terrain << ".png)\n";
  }
  for (const std::string& note : notes) md << "\n" << note << "\n";
  WriteTextFileAtomically((folder / "results.md").string(), md.str());
}

}  // namespace trav::scenarios
