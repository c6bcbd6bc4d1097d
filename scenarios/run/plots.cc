#include "scenarios/run/plots.h"

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <fmt/format.h>
#include <sys/wait.h>

#include "common/input_error.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/process_pool.h"

extern char** environ;

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

// The compute columns of timeseries.csv and their legend titles.
constexpr std::pair<const char*, const char*> kComputeColumns[] = {
    {"lidar_ms", "lidar"},     {"mapping_ms", "mapping"}, {"planning_ms", "planning"},
    {"control_ms", "control"}, {"physics_ms", "physics"}, {"render_ms", "render"}};

constexpr const char* kTimeLabel = "simulation time [s]";

// At most this much of gnuplot's error output goes into a result's message.
constexpr std::size_t kMaxErrorChars = 600;

// A CSV file of numbers with a header line.
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;

  std::optional<std::size_t> Column(const std::string& name) const {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      if (columns[i] == name) return i;
    }
    return std::nullopt;
  }
};

std::vector<std::string> SplitFields(std::string line) {
  if (!line.empty() && line.back() == '\r') line.pop_back();
  std::vector<std::string> fields;
  std::stringstream stream(line);
  for (std::string field; std::getline(stream, field, ',');) fields.push_back(field);
  // a trailing comma ends with an empty field getline does not return
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

// Reads a CSV file; fields that are not numbers read as NaN, and rows whose field count differs
// from the header's (a truncated last line) are dropped.
Table ReadCsv(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error("cannot read " + path);
  Table table;
  std::string line;
  if (!std::getline(file, line)) return table;
  table.columns = SplitFields(line);
  while (std::getline(file, line)) {
    const std::vector<std::string> fields = SplitFields(line);
    if (fields.size() != table.columns.size()) continue;
    std::vector<double> row(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
      char* end = nullptr;
      row[i] = std::strtod(fields[i].c_str(), &end);
      if (end == fields[i].c_str()) row[i] = std::nan("");
    }
    table.rows.push_back(std::move(row));
  }
  if (file.bad()) throw std::runtime_error("cannot read " + path);
  return table;
}

// A gnuplot string literal: single quotes take everything literally except '' for a quote, and
// a line break ends the command, so control characters become spaces: no label (a scenario
// name, a batch's parameter) can add a command to the script.
std::string Quote(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    quoted += byte < 0x20 || byte == 0x7f ? ' ' : c;
    if (c == '\'') quoted += '\'';
  }
  return quoted + "'";
}

// The CSV columns a plot draws: x, then per series its column and its band's edges if any.
std::vector<std::string> PlotColumns(const LinePlot& spec) {
  std::vector<std::string> columns = {spec.x_column};
  for (const PlotSeries& series : spec.series) {
    columns.push_back(series.column);
    if (!series.band_low.empty()) {
      columns.push_back(series.band_low);
      columns.push_back(series.band_high);
    }
  }
  return columns;
}

// The rows of `spec` as "x value..." lines (PlotColumns' order), skipping rows with a non-finite
// value; empty when no row has one.
std::string DataBlock(const Table& table, const LinePlot& spec) {
  std::vector<std::size_t> indices;
  for (const std::string& column : PlotColumns(spec)) indices.push_back(*table.Column(column));
  std::string block;
  for (const std::vector<double>& row : table.rows) {
    bool finite = true;
    for (const std::size_t i : indices) finite = finite && std::isfinite(row[i]);
    if (!finite) continue;
    for (std::size_t k = 0; k < indices.size(); ++k) {
      if (k > 0) block += ' ';
      fmt::format_to(std::back_inserter(block), "{:.6g}", row[indices[k]]);
    }
    block += '\n';
  }
  return block;
}

// The colours of a plot's series, in order (Okabe and Ito's colour-blind safe palette).
constexpr const char* kSeriesColours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                          "#E69F00", "#56B4E9", "#000000", "#F0E442"};

// Rows up to which a curve carries a marker at each row.
constexpr std::size_t kMaxMarkedRows = 30;

// The gnuplot plot command of `spec` over the data block `data` of `rows` rows: every band first
// (translucent, behind the curves), then the curves.
std::string PlotCommand(const LinePlot& spec, const std::string& data, std::size_t rows) {
  std::vector<std::string> bands, curves;
  std::size_t column = 2;
  for (std::size_t s = 0; s < spec.series.size(); ++s) {
    const PlotSeries& series = spec.series[s];
    const std::string colour =
        std::string("lc rgb '") + kSeriesColours[s % std::size(kSeriesColours)] + "'";
    const std::string style = spec.dots                ? " with points pt 7 ps 0.3 "
                              : rows <= kMaxMarkedRows ? " with linespoints lw 2 pt 7 ps 0.8 "
                                                       : " with lines lw 1.5 ";
    curves.push_back(data + " using 1:" + std::to_string(column) + style + colour + " title " +
                     Quote(series.title));
    ++column;
    if (series.band_low.empty()) continue;
    bands.push_back(
        data + " using 1:" + std::to_string(column) + ":" + std::to_string(column + 1) +
        " with filledcurves fs transparent solid 0.2 noborder " + colour + " title " +
        Quote(series.band_title.empty() ? series.title + " (interval)" : series.band_title));
    column += 2;
  }
  std::string command = "plot ";
  bands.insert(bands.end(), curves.begin(), curves.end());
  for (std::size_t i = 0; i < bands.size(); ++i) command += (i == 0 ? "" : ", ") + bands[i];
  return command + "\n";
}

// Every finite value of the plot's series.
std::vector<double> SeriesValues(const Table& table, const LinePlot& spec) {
  std::vector<double> values;
  for (const PlotSeries& series : spec.series) {
    const std::optional<std::size_t> column = table.Column(series.column);
    if (!column) continue;
    for (const std::vector<double>& row : table.rows) {
      if (std::isfinite(row[*column])) values.push_back(row[*column]);
    }
  }
  return values;
}

// The gnuplot lines of a plot's title, axis labels and y range (clipped as RobustUpperLimit says
// when the plot asks for it, and the title then says so).
std::string Labels(const Table& table, const LinePlot& spec) {
  const std::vector<double> values =
      spec.clip_spikes ? SeriesValues(table, spec) : std::vector<double>{};
  const std::optional<double> top = RobustUpperLimit(values);
  const std::string clipped = top ? fmt::format(" (clipped at {:.3g}; largest {:.3g})", *top,
                                                *std::max_element(values.begin(), values.end()))
                                  : "";
  const std::string top_text = top ? fmt::format("{:.6g}", *top) : "*";
  const std::string y_range =
      spec.y_range
          ? fmt::format("set yrange [{:.6g}:{:.6g}]\n", spec.y_range->first, spec.y_range->second)
          : (spec.y_from_zero ? "set yrange [0:" : "set yrange [*:") + top_text + "]\n";
  return "set title " + Quote(spec.title + clipped) + "\nset xlabel " + Quote(spec.x_label) +
         "\nset ylabel " + Quote(spec.y_label) + "\n" + y_range;
}

// The y label of the compute plot, with the mean interval between rows (each row holds the
// wall time spent since the previous one).
std::string ComputeLabel(const Table& table) {
  const std::optional<std::size_t> t = table.Column("t");
  if (!t || table.rows.size() < 2) return "wall time per row interval [ms]";
  const double interval_s =
      (table.rows.back()[*t] - table.rows.front()[*t]) / static_cast<double>(table.rows.size() - 1);
  if (!std::isfinite(interval_s) || interval_s <= 0.0) return "wall time per row interval [ms]";
  return fmt::format("wall time per {:.3g} s of simulation [ms]", interval_s);
}

// The plots of timeseries.csv: speed, roll and pitch, mapping error, and compute when the file
// has compute columns (else a reason in `reasons`).
std::vector<LinePlot> RunPlotSpecs(const Table& table, std::vector<std::string>* reasons) {
  std::vector<LinePlot> specs = {
      {"speed.png",
       "Forward speed",
       "t",
       kTimeLabel,
       "speed [m/s]",
       {{"v_forward", "measured (v_forward)"}, {"cmd_v", "commanded (cmd_v)"}},
       false},
      {"roll_pitch.png",
       "Roll and pitch of the base",
       "t",
       kTimeLabel,
       "angle [deg]",
       {{"roll_deg", "roll"}, {"pitch_deg", "pitch"}},
       false},
      {"mapping_error.png",
       "Mapping error against the ground truth",
       "t",
       kTimeLabel,
       "mean |traversability - ground truth|",
       {{"mapping_error", "mapping error"}},
       true},
  };
  // the first rows carry the set-up (the first plan, the first map): clipped, not flattening
  LinePlot compute{
      "compute.png", "Compute per module", "t", kTimeLabel, ComputeLabel(table), {}, true, false,
      true};
  for (const auto& [column, title] : kComputeColumns) {
    if (table.Column(column)) compute.series.push_back({column, title});
  }
  if (compute.series.empty()) {
    reasons->push_back("compute.png: no compute columns in timeseries.csv");
  } else {
    specs.push_back(std::move(compute));
  }
  return specs;
}

// Removes the files it holds when it goes out of scope.
class TemporaryFiles {
 public:
  TemporaryFiles() = default;
  TemporaryFiles(const TemporaryFiles&) = delete;
  TemporaryFiles& operator=(const TemporaryFiles&) = delete;
  ~TemporaryFiles() {
    std::error_code error;
    for (const std::string& path : paths_) fs::remove(path, error);
  }
  std::string Add(const std::string& path) {
    paths_.push_back(path);
    return path;
  }

 private:
  std::vector<std::string> paths_;
};

// The start of a text file, whitespace collapsed to single spaces.
std::string ErrorText(const std::string& path) {
  std::ifstream file(path);
  std::string text;
  for (std::string word; file >> word && text.size() < kMaxErrorChars;) {
    text += (text.empty() ? "" : " ") + word;
  }
  return text.substr(0, kMaxErrorChars);
}

std::string Join(const std::vector<std::string>& parts) {
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : "; ") + part;
  return text;
}

void ValidatePlotOptions(const PlotOptions& options) {
  common::RequireValue(options.width >= 100 && options.width <= 4096, "plots.width", options.width,
                       "must be in [100, 4096]");
  common::RequireValue(options.height >= 100 && options.height <= 4096, "plots.height",
                       options.height, "must be in [100, 4096]");
}

PlotResult NoGnuplot(const PlotOptions& options) {
  PlotResult result;
  result.status = PlotStatus::kNoGnuplot;
  result.message = "no plots: gnuplot is not installed (no '" + options.gnuplot +
                   "' on the PATH; install the gnuplot-nox package)";
  return result;
}

// Writes the plots of `table` that have their columns and at least one row of finite values into
// `output_dir`; `reasons` already lists plots left out by the caller.
PlotResult PlotTable(const Table& table, const std::vector<LinePlot>& specs,
                     std::vector<std::string> reasons, const std::string& output_dir,
                     const PlotOptions& options) {
  PlotResult result;
  const fs::path folder(output_dir);
  std::vector<std::pair<LinePlot, std::string>> plots;
  for (const LinePlot& spec : specs) {
    std::string missing;
    for (const std::string& column : PlotColumns(spec)) {
      if (!table.Column(column)) missing += (missing.empty() ? "" : ", ") + column;
    }
    if (!missing.empty()) {
      reasons.push_back(spec.file + ": no column " + missing);
      continue;
    }
    std::string block = DataBlock(table, spec);
    if (block.empty()) {
      reasons.push_back(spec.file + ": no row with values");
    } else {
      plots.emplace_back(spec, std::move(block));
    }
  }
  if (plots.empty()) {
    result.message = Join(reasons);
    return result;
  }

  // the script: the style, then per plot its data block, the PNG, and the same plot as SVG
  const std::string tag = std::to_string(getpid());
  TemporaryFiles temporary;
  const std::string script_path = temporary.Add((folder / (".plots-" + tag + ".gp")).string());
  const std::string log_path = temporary.Add((folder / (".plots-" + tag + ".log")).string());
  const std::string size = std::to_string(options.width) + "," + std::to_string(options.height);
  std::string script =
      "png_terminal = strstrt(GPVAL_TERMINALS, 'pngcairo') > 0 ? 'pngcairo' : 'png'\n"
      "set grid lc rgb '#d8d8d8' lw 1\n"
      "set border 3 lc rgb '#404040'\n"
      "set tics nomirror\n"
      "set key above horizontal\n"
      "set autoscale xfix\n"
      "set offsets 0, 0, graph 0.02, graph 0.02\n";
  std::vector<std::pair<std::string, std::string>> partial_paths;  // PNG, SVG
  for (std::size_t p = 0; p < plots.size(); ++p) {
    const auto& [spec, block] = plots[p];
    const std::string data = "$data" + std::to_string(p);
    partial_paths.emplace_back(
        temporary.Add((folder / ("." + spec.file + ".partial-" + tag)).string()),
        temporary.Add((folder / ("." + SvgName(spec.file) + ".partial-" + tag)).string()));
    script += data + " << EOD\n" + block + "EOD\n";
    script += "set terminal png_terminal size " + size + " noenhanced font ',10'\n";
    script += "set output " + Quote(partial_paths.back().first) + "\n";
    script += Labels(table, spec);
    script += PlotCommand(spec, data,
                          static_cast<std::size_t>(std::count(block.begin(), block.end(), '\n')));
    script += "set terminal svg size " + size + " noenhanced dynamic font 'sans,10'\n";
    script += "set output " + Quote(partial_paths.back().second) + "\n";
    script += "replot\nunset output\n";
  }
  WriteTextFile(script_path, script);

  // gnuplot, then the images under their final names only if every one of them was written
  const ProcessResult run = RunProcess({{options.gnuplot, script_path}, log_path});
  if (run.end == ProcessEnd::kNotStarted) throw std::runtime_error(run.message);
  const int exit_status = run.end == ProcessEnd::kExited ? run.exit_code : -1;
  std::error_code error;
  bool complete = exit_status == 0;
  for (const auto& [png, svg] : partial_paths) {
    for (const std::string& path : {png, svg}) {
      complete = complete && fs::is_regular_file(path, error) && fs::file_size(path, error) > 0;
    }
  }
  if (!complete) {
    result.status = PlotStatus::kGnuplotFailed;
    result.message = "no plots: " + options.gnuplot + " failed (exit status " +
                     std::to_string(exit_status) + "): " + ErrorText(log_path);
    return result;
  }
  for (std::size_t p = 0; p < plots.size(); ++p) {
    const std::string& file = plots[p].first.file;
    for (const auto& [partial, name] : {std::pair(partial_paths[p].first, file),
                                        std::pair(partial_paths[p].second, SvgName(file))}) {
      fs::rename(partial, folder / name, error);
      if (error) {
        throw std::runtime_error("cannot write " + (folder / name).string() + ": " +
                                 error.message());
      }
    }
    result.written.push_back(file);
  }
  result.message = Join(reasons);
  return result;
}

}  // namespace

std::optional<double> RobustUpperLimit(std::vector<double> values) {
  values.erase(
      std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }),
      values.end());
  constexpr std::size_t kMinimumValues = 20;
  if (values.size() < kMinimumValues) return std::nullopt;
  const auto at = values.begin() + static_cast<std::ptrdiff_t>(0.99 * (values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  const double percentile = *at;
  const double largest = *std::max_element(at, values.end());
  if (!(percentile > 0.0) || largest <= 2.0 * percentile) return std::nullopt;
  return 1.2 * percentile;
}

std::string SvgName(const std::string& png_file) {
  return fs::path(png_file).replace_extension(".svg").string();
}

bool ProgramAvailable(const std::string& program) {
  if (program.empty()) return false;
  if (program.find('/') != std::string::npos) return access(program.c_str(), X_OK) == 0;
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::stringstream directories(path);
  for (std::string directory; std::getline(directories, directory, ':');) {
    if (!directory.empty() && access((directory + "/" + program).c_str(), X_OK) == 0) return true;
  }
  return false;
}

PlotResult WriteLinePlots(const std::string& csv_path, const std::vector<LinePlot>& plots,
                          const std::string& output_dir, const PlotOptions& options) {
  ValidatePlotOptions(options);
  if (!ProgramAvailable(options.gnuplot)) return NoGnuplot(options);
  return PlotTable(ReadCsv(csv_path), plots, {}, output_dir, options);
}

PlotResult WriteRunPlots(const std::string& output_dir, const PlotOptions& options) {
  ValidatePlotOptions(options);
  const std::string csv_path = (fs::path(output_dir) / "timeseries.csv").string();
  std::error_code error;
  if (!fs::is_regular_file(csv_path, error)) {
    PlotResult result;
    result.status = PlotStatus::kNoTimeseries;
    result.message = "no plots: " + csv_path + " does not exist (written in mode navigate)";
    return result;
  }
  if (!ProgramAvailable(options.gnuplot)) return NoGnuplot(options);
  const Table table = ReadCsv(csv_path);
  std::vector<std::string> reasons;
  const std::vector<LinePlot> specs = RunPlotSpecs(table, &reasons);
  return PlotTable(table, specs, reasons, output_dir, options);
}

nlohmann::json PlotsJson(const PlotResult& result) {
  if (!result.ok()) return nullptr;
  return result.written;
}

}  // namespace trav::scenarios
