#include "scenarios/run/pattern_report.h"

#include <cmath>
#include <filesystem>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "common/input_error.h"
#include "sim/lidar/scan_pattern.h"
#include "sim/lidar/scan_pattern_statistics.h"

namespace trav::scenarios {
namespace {

constexpr std::int64_t kRaysPerFrame = 20000;  // the MID-360: 200,000 points/s at 10 Hz
constexpr double kRadToDeg = 180.0 / M_PI;

struct NamedPattern {
  std::string name;
  std::shared_ptr<const lidar::ScanPattern> pattern;
};

nlohmann::json StatisticsJson(const lidar::PatternStatistics& stats) {
  return {{"rays", stats.rays},
          {"covered_cells", stats.covered_cells},
          {"coverage", stats.coverage},
          {"elevation_share", stats.elevation_share},
          {"azimuth_share", stats.azimuth_share}};
}

nlohmann::json PatternJson(const NamedPattern& named, const lidar::PatternStatistics& reference,
                           int frames) {
  const lidar::ScanPattern& pattern = *named.pattern;
  const lidar::PatternStatistics one = lidar::ComputePatternStatistics(pattern, 0, kRaysPerFrame);
  std::vector<double> coverage;
  for (int n = 1; n <= frames; ++n) {
    coverage.push_back(lidar::ComputePatternStatistics(pattern, 0, n * kRaysPerFrame).coverage);
  }
  return {{"one_frame", StatisticsJson(one)},
          {"all_frames", StatisticsJson(lidar::ComputePatternStatistics(
                             pattern, 0, static_cast<std::int64_t>(frames) * kRaysPerFrame))},
          {"coverage_by_frames", coverage},
          {"elevation_total_variation_vs_mid360",
           lidar::TotalVariation(one.elevation_share, reference.elevation_share)},
          {"azimuth_total_variation_vs_mid360",
           lidar::TotalVariation(one.azimuth_share, reference.azimuth_share)}};
}

// The first frame of every pattern: columns azimuth_<name>, elevation_<name> [deg].
std::string RaysCsv(const std::vector<NamedPattern>& patterns) {
  std::string csv;
  for (const NamedPattern& named : patterns) {
    csv += (csv.empty() ? "" : ",") + ("azimuth_" + named.name) + ",elevation_" + named.name;
  }
  csv += '\n';
  for (std::int64_t i = 0; i < kRaysPerFrame; ++i) {
    for (std::size_t p = 0; p < patterns.size(); ++p) {
      const Eigen::Vector3f direction = patterns[p].pattern->Ray(i).direction_L;
      double azimuth_deg = lidar::Azimuth(direction) * kRadToDeg;
      if (azimuth_deg < 0.0) azimuth_deg += 360.0;
      fmt::format_to(std::back_inserter(csv), "{}{:.4f},{:.4f}", p == 0 ? "" : ",", azimuth_deg,
                     lidar::Elevation(direction) * kRadToDeg);
    }
    csv += '\n';
  }
  return csv;
}

LinePlot RaysPlot(const std::string& name) {
  LinePlot plot;
  plot.file = "pattern_" + name + ".png";
  plot.title = "one 100 ms frame of the " + name + " pattern (20,000 rays)";
  plot.x_column = "azimuth_" + name;
  plot.x_label = "azimuth [deg]";
  plot.y_label = "elevation [deg]";
  plot.series = {{"elevation_" + name, name}};
  plot.dots = true;
  plot.y_range = {{-10.0, 55.0}};
  return plot;
}

}  // namespace

nlohmann::json WritePatternReport(const PatternReportOptions& options, const OutputFolder& folder) {
  common::RequireValue(options.frames >= 1 && options.frames <= 100, "--frames", options.frames,
                       "must be in [1, 100]");
  std::vector<NamedPattern> patterns = {
      {"mid360", lidar::TablePattern::Mid360()},
      {"procedural", std::make_shared<lidar::ProceduralMid360Pattern>()}};
  if (!options.table.empty())
    patterns.push_back({"table", lidar::TablePattern::Load(options.table)});

  const lidar::PatternStatistics reference =
      lidar::ComputePatternStatistics(*patterns.front().pattern, 0, kRaysPerFrame);
  nlohmann::json report = {{"rays_per_frame", kRaysPerFrame},
                           {"frames", options.frames},
                           {"elevation_bands_deg", "5 deg from [-10, -5) to [50, 55)"},
                           {"azimuth_bands_deg", "30 deg from [0, 30) to [330, 360)"},
                           {"field_cells", "1 x 1 deg, elevation [-7, 52) deg: 21240"},
                           {"patterns", nlohmann::json::object()}};
  for (const NamedPattern& named : patterns) {
    report["patterns"][named.name] = PatternJson(named, reference, options.frames);
  }
  if (!options.table.empty()) report["table"] = options.table;

  const std::string csv_path = folder.File("pattern_rays.csv");
  WriteTextFile(csv_path, RaysCsv(patterns));
  std::vector<LinePlot> plots;
  for (const NamedPattern& named : patterns) plots.push_back(RaysPlot(named.name));
  const PlotResult plotted = WriteLinePlots(
      csv_path, plots, std::filesystem::path(csv_path).parent_path().string(), options.plots);
  report["plots"] = PlotsJson(plotted);
  WriteTextFile(folder.File("pattern_statistics.json"), report.dump(2) + "\n");
  return report;
}

}  // namespace trav::scenarios
