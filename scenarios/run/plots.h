#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace trav::scenarios {

/// Settings of the plots of a run.
struct PlotOptions {
  int width{800};   ///< image width [pixels], 100..4096
  int height{480};  ///< image height [pixels], 100..4096
  /// The gnuplot program: a name looked up on the PATH, or a path (containing '/').
  std::string gnuplot{"gnuplot"};
};

/// How writing the plots of a run went.
enum class PlotStatus {
  kWritten,        ///< gnuplot ran; `PlotResult::written` lists the plots that had data
  kNoGnuplot,      ///< gnuplot is not installed: nothing written
  kNoTimeseries,   ///< the folder has no timeseries.csv (a run of mode navigate writes it)
  kGnuplotFailed,  ///< gnuplot ran but failed: nothing written (its error in the message)
};

/// The plots of a run that were written, and why the others were not.
struct PlotResult {
  PlotStatus status{PlotStatus::kWritten};
  /// PNG names written into the output folder, in the order speed.png, roll_pitch.png,
  /// mapping_error.png, compute.png (each only if it had data); each has its SVG beside it.
  std::vector<std::string> written;
  /// Why plots are missing ("gnuplot is not installed ...", "compute.png: no compute columns
  /// ..."); empty when every plot was written.
  std::string message;

  [[nodiscard]] bool ok() const { return status == PlotStatus::kWritten; }
};

/// One curve of a line plot: a column of a CSV file against the plot's x column, with an optional
/// band between two other columns (an interval: drawn as a translucent area of the curve's colour
/// behind it, titled `band_title`).
struct PlotSeries {
  std::string column;
  std::string title;
  std::string band_low{};   ///< column of the band's lower edge; empty: no band
  std::string band_high{};  ///< column of the band's upper edge
  std::string band_title{};
};

/// One line plot of columns of a CSV file, written as PNG and as SVG beside it. Every plot has
/// the same style: a light grid, the legend above the axes (never over the data or the labels),
/// one colour per series in a fixed order, markers at the rows when there are at most 30.
struct LinePlot {
  std::string file;  ///< PNG name in the output folder ("speed.png"); the SVG: "speed.svg"
  std::string title;
  std::string x_column{"t"};
  std::string x_label{"simulation time [s]"};
  std::string y_label;
  std::vector<PlotSeries> series;
  bool y_from_zero{false};  ///< values are never negative
  bool dots{false};         ///< a dot at every row and no lines (a scatter plot)
  /// A few values far above the rest (a first frame's setup) do not set the scale: the y range
  /// ends at RobustUpperLimit, and the title says so and gives the largest value.
  bool clip_spikes{false};
  /// A fixed y range [min, max] (plots to be compared side by side); else from the data.
  std::optional<std::pair<double, double>> y_range{};
};

/// The top of a y range for `values` (non-finite ones ignored) that a few spikes do not flatten:
/// 1.2 times the 99th percentile when the largest value exceeds twice it; nothing when there is no
/// such spike or fewer than 20 finite values.
std::optional<double> RobustUpperLimit(std::vector<double> values);

/// Writes `plots` of the CSV file `csv_path` (a header line, then numbers; fields that are not
/// numbers read as missing) with gnuplot into `output_dir`, as WriteRunPlots does: a plot whose
/// columns are absent, or with no row of finite values, is skipped with its reason in the
/// message; images appear under their final names only when gnuplot has written all of them.
/// @throws common::InputError if the options are out of range; std::runtime_error if the file
/// cannot be read, or gnuplot cannot be started although found.
[[nodiscard]] PlotResult WriteLinePlots(const std::string& csv_path,
                                        const std::vector<LinePlot>& plots,
                                        const std::string& output_dir,
                                        const PlotOptions& options = {});

/// Reads `output_dir`/timeseries.csv (as the runner writes it in mode navigate: columns t,
/// v_forward, cmd_v, roll_deg, pitch_deg, mapping_error and, when present, the compute columns
/// lidar_ms, mapping_ms, planning_ms, control_ms, physics_ms, render_ms) and writes with gnuplot
/// (terminal pngcairo, or png where gnuplot has no cairo) into `output_dir`:
/// - speed.png: v_forward and cmd_v over t [m/s];
/// - roll_pitch.png: roll_deg and pitch_deg over t [deg];
/// - mapping_error.png: mapping_error over t, rows without a value (NaN) skipped; not written
///   when no row has one (mapping off);
/// - compute.png: the wall time of each module per row interval over t [ms]; not written when
///   the file has none of the compute columns.
/// A plot is skipped when one of its columns is absent or none of its rows has finite values;
/// rows with a field count other than the header's (a truncated last line) are ignored. Each PNG
/// has an SVG of the same name beside it. The gnuplot script is a temporary file in
/// `output_dir`, removed afterwards, and each image is written under a temporary name and renamed
/// once gnuplot has succeeded, so no half-written image is ever left under a final name. A missing
/// gnuplot or timeseries.csv, or a failing gnuplot, is reported in the result, not thrown.
/// @throws common::InputError if the options are out of range; std::runtime_error if
/// timeseries.csv exists but cannot be read, or gnuplot cannot be started although found.
[[nodiscard]] PlotResult WriteRunPlots(const std::string& output_dir,
                                       const PlotOptions& options = {});

/// The SVG written beside the PNG `png_file` ("speed.png" -> "speed.svg").
std::string SvgName(const std::string& png_file);

/// summary.json's "plots": the written PNG names as an array when gnuplot ran, else null.
nlohmann::json PlotsJson(const PlotResult& result);

/// Whether `program` (a name on the PATH, or a path containing '/') is an executable file.
bool ProgramAvailable(const std::string& program);

}  // namespace trav::scenarios
