#include "scenarios/plots.h"

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <sys/wait.h>

#include "common/input_error.h"

extern char** environ;

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

// The compute columns of timeseries.csv and their legend titles.
constexpr std::pair<const char*, const char*> kComputeColumns[] = {
    {"lidar_ms", "lidar"},     {"mapping_ms", "mapping"}, {"planning_ms", "planning"},
    {"control_ms", "control"}, {"physics_ms", "physics"}, {"render_ms", "render"}};

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

// One curve of a plot: a column of the table against t.
struct Series {
  std::string column;
  std::string title;
};

// One image: its curves and labels.
struct PlotSpec {
  std::string file;
  std::string title;
  std::string y_label;
  std::vector<Series> series;
  bool y_from_zero{false};  // values are never negative
};

// A gnuplot string literal: single quotes take everything literally except '' for a quote.
std::string Quote(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) {
    quoted += c;
    if (c == '\'') quoted += '\'';
  }
  return quoted + "'";
}

// The rows of `spec` as "t value..." lines, skipping rows with a non-finite value; empty when no
// row has one.
std::string DataBlock(const Table& table, const PlotSpec& spec) {
  std::vector<std::size_t> indices = {*table.Column("t")};
  for (const Series& series : spec.series) indices.push_back(*table.Column(series.column));
  std::string block;
  char number[32];
  for (const std::vector<double>& row : table.rows) {
    bool finite = true;
    for (const std::size_t i : indices) finite = finite && std::isfinite(row[i]);
    if (!finite) continue;
    for (std::size_t k = 0; k < indices.size(); ++k) {
      std::snprintf(number, sizeof(number), k == 0 ? "%.6g" : " %.6g", row[indices[k]]);
      block += number;
    }
    block += '\n';
  }
  return block;
}

// The y label of the compute plot, with the mean interval between rows (each row holds the
// wall time spent since the previous one).
std::string ComputeLabel(const Table& table) {
  const std::optional<std::size_t> t = table.Column("t");
  if (!t || table.rows.size() < 2) return "wall time per row interval [ms]";
  const double interval_s =
      (table.rows.back()[*t] - table.rows.front()[*t]) / static_cast<double>(table.rows.size() - 1);
  if (!std::isfinite(interval_s) || interval_s <= 0.0) return "wall time per row interval [ms]";
  char label[96];
  std::snprintf(label, sizeof(label), "wall time per %.3g s of simulation [ms]", interval_s);
  return label;
}

// The plots timeseries.csv has the columns for, and why the others are left out.
std::vector<PlotSpec> PlotSpecs(const Table& table, std::vector<std::string>* reasons) {
  std::vector<PlotSpec> candidates = {
      {"speed.png",
       "Forward speed",
       "speed [m/s]",
       {{"v_forward", "measured (v_forward)"}, {"cmd_v", "commanded (cmd_v)"}},
       false},
      {"roll_pitch.png",
       "Roll and pitch of the base",
       "angle [deg]",
       {{"roll_deg", "roll"}, {"pitch_deg", "pitch"}},
       false},
      {"mapping_error.png",
       "Mapping error against the ground truth",
       "mean |traversability - ground truth|",
       {{"mapping_error", "mapping error"}},
       true},
  };
  PlotSpec compute{"compute.png", "Compute per module", ComputeLabel(table), {}, true};
  for (const auto& [column, title] : kComputeColumns) {
    if (table.Column(column)) compute.series.push_back({column, title});
  }
  if (compute.series.empty()) {
    reasons->push_back("compute.png: no compute columns in timeseries.csv");
  } else {
    candidates.push_back(std::move(compute));
  }

  std::vector<PlotSpec> specs;
  for (PlotSpec& spec : candidates) {
    std::string missing = table.Column("t") ? "" : "t";
    for (const Series& series : spec.series) {
      if (!table.Column(series.column)) missing += (missing.empty() ? "" : ", ") + series.column;
    }
    if (missing.empty()) {
      specs.push_back(std::move(spec));
    } else {
      reasons->push_back(spec.file + ": no column " + missing + " in timeseries.csv");
    }
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

// Runs `program` on `script` with its error output into `log`, and returns its exit status (-1
// when it did not exit normally). @throws std::runtime_error if it cannot be started.
int RunGnuplot(const std::string& program, const std::string& script, const std::string& log) {
  std::vector<std::string> args = {program, script};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);

  // no terminal input, no output but errors, which go to the log
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  const int status = posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (status != 0) {
    throw std::runtime_error("cannot start " + program + ": " + std::strerror(status));
  }
  int exit_status = 0;
  while (waitpid(pid, &exit_status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error("cannot wait for " + program);
  }
  return WIFEXITED(exit_status) ? WEXITSTATUS(exit_status) : -1;
}

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

}  // namespace

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

PlotResult WriteRunPlots(const std::string& output_dir, const PlotOptions& options) {
  common::RequireValue(options.width >= 100 && options.width <= 4096, "plots.width", options.width,
                       "must be in [100, 4096]");
  common::RequireValue(options.height >= 100 && options.height <= 4096, "plots.height",
                       options.height, "must be in [100, 4096]");
  PlotResult result;
  const fs::path folder(output_dir);
  const std::string csv_path = (folder / "timeseries.csv").string();
  std::error_code error;
  if (!fs::is_regular_file(csv_path, error)) {
    result.status = PlotStatus::kNoTimeseries;
    result.message = "no plots: " + csv_path + " does not exist (written in mode navigate)";
    return result;
  }
  if (!ProgramAvailable(options.gnuplot)) {
    result.status = PlotStatus::kNoGnuplot;
    result.message = "no plots: gnuplot is not installed (no '" + options.gnuplot +
                     "' on the PATH; install the gnuplot-nox package)";
    return result;
  }

  // the plots that have their columns and at least one row of finite values
  const Table table = ReadCsv(csv_path);
  std::vector<std::string> reasons;
  std::vector<PlotSpec> specs = PlotSpecs(table, &reasons);
  std::vector<std::pair<PlotSpec, std::string>> plots;
  for (PlotSpec& spec : specs) {
    std::string block = DataBlock(table, spec);
    if (block.empty()) {
      reasons.push_back(spec.file + ": no row with values in timeseries.csv");
    } else {
      plots.emplace_back(std::move(spec), std::move(block));
    }
  }
  if (plots.empty()) {
    result.message = Join(reasons);
    return result;
  }

  // the script: terminal, then per plot its data block, temporary output and curves
  const std::string tag = std::to_string(getpid());
  TemporaryFiles temporary;
  const std::string script_path = temporary.Add((folder / (".plots-" + tag + ".gp")).string());
  const std::string log_path = temporary.Add((folder / (".plots-" + tag + ".log")).string());
  const std::string size = std::to_string(options.width) + "," + std::to_string(options.height);
  std::string script =
      "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
      "  set terminal pngcairo size " +
      size +
      " noenhanced\n"
      "} else {\n"
      "  set terminal png size " +
      size +
      " noenhanced\n"
      "}\n"
      "set grid\n"
      "set key below horizontal\n"
      "set autoscale xfix\n"
      "set xlabel 'simulation time [s]'\n";
  std::vector<std::string> partial_paths;
  for (std::size_t p = 0; p < plots.size(); ++p) {
    const auto& [spec, block] = plots[p];
    const std::string data = "$data" + std::to_string(p);
    partial_paths.push_back(
        temporary.Add((folder / ("." + spec.file + ".partial-" + tag)).string()));
    script += data + " << EOD\n" + block + "EOD\n";
    script += "set output " + Quote(partial_paths.back()) + "\n";
    script += "set title " + Quote(spec.title) + "\n";
    script += "set ylabel " + Quote(spec.y_label) + "\n";
    script += spec.y_from_zero ? "set yrange [0:*]\n" : "set yrange [*:*]\n";
    script += "plot ";
    for (std::size_t s = 0; s < spec.series.size(); ++s) {
      script += (s == 0 ? "" : ", ") + data + " using 1:" + std::to_string(s + 2) +
                " with lines lw 1.5 title " + Quote(spec.series[s].title);
    }
    script += "\nunset output\n";
  }
  {
    std::ofstream file(script_path);
    file << script;
    if (!file) throw std::runtime_error("cannot write " + script_path);
  }

  // gnuplot, then the images under their final names only if every one of them was written
  const int exit_status = RunGnuplot(options.gnuplot, script_path, log_path);
  bool complete = exit_status == 0;
  for (const std::string& path : partial_paths) {
    complete = complete && fs::is_regular_file(path, error) && fs::file_size(path, error) > 0;
  }
  if (!complete) {
    result.status = PlotStatus::kGnuplotFailed;
    result.message = "no plots: " + options.gnuplot + " failed (exit status " +
                     std::to_string(exit_status) + "): " + ErrorText(log_path);
    return result;
  }
  for (std::size_t p = 0; p < plots.size(); ++p) {
    const std::string& file = plots[p].first.file;
    fs::rename(partial_paths[p], folder / file, error);
    if (error) {
      throw std::runtime_error("cannot write " + (folder / file).string() + ": " + error.message());
    }
    result.written.push_back(file);
  }
  result.message = Join(reasons);
  return result;
}

nlohmann::json PlotsJson(const PlotResult& result) {
  if (!result.ok()) return nullptr;
  return result.written;
}

}  // namespace trav::scenarios
