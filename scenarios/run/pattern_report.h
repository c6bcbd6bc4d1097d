#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "scenarios/run/output_folder.h"
#include "scenarios/run/plots.h"

namespace trav::scenarios {

/// What `trav pattern` compares: the MID-360's shipped table (`mid360`, the default pattern), the
/// procedural model (`procedural`) and, when named, a user's Livox scan table (`table`).
struct PatternReportOptions {
  int frames{2};      ///< frames for the accumulated statistics (>= 1, <= 100)
  std::string table;  ///< a scan table to compare as well; empty: none
  PlotOptions plots;
};

/// Writes into `folder`:
/// - pattern_statistics.json: per pattern, the statistics (sim/lidar/scan_pattern_statistics.h)
///   of its first frame and of its first `frames` frames (20,000 rays each, the MID-360 at
///   200,000 points/s and 10 Hz), the coverage after 1 .. `frames` frames, and the total variation
///   of its elevation and azimuth histograms from the shipped table's;
/// - pattern_rays.csv: the azimuth and elevation [deg] of every ray of each pattern's first frame;
/// - pattern_<name>.png: that frame as dots, azimuth against elevation (when gnuplot is there).
/// Returns pattern_statistics.json's content, with "plots" (PlotsJson).
/// @throws common::InputError for options out of range or a bad table (naming the file and line).
nlohmann::json WritePatternReport(const PatternReportOptions& options, const OutputFolder& folder);

}  // namespace trav::scenarios
