// trav pattern: the MID-360 scan patterns compared (statistics, rays and plots).
#include <cstdio>
#include <memory>
#include <string>

#include "common/input_error.h"
#include "scenarios/cli/cli.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/pattern_report.h"

namespace trav::scenarios::cli {
namespace {

struct PatternFlags {
  std::string out;
  bool overwrite{false};
  PatternReportOptions report;
};

int Pattern(const PatternFlags& flags) {
  if (flags.out.empty()) throw common::InputError("--out", "", "trav pattern needs --out DIR");
  OutputFolder folder(flags.out, "pattern", flags.overwrite);
  const nlohmann::json report = WritePatternReport(flags.report, folder);
  folder.Commit();
  for (const auto& [name, pattern] : report["patterns"].items()) {
    std::printf(
        "%-10s one frame covers %5.1f %% of the field, %d frames %5.1f %%; elevation histogram "
        "%4.1f %% from mid360's\n",
        name.c_str(), 100.0 * pattern["one_frame"]["coverage"].get<double>(), flags.report.frames,
        100.0 * pattern["all_frames"]["coverage"].get<double>(),
        100.0 * pattern["elevation_total_variation_vs_mid360"].get<double>());
  }
  std::printf("written to %s (pattern_statistics.json, pattern_rays.csv, pattern_*.png)\n",
              folder.final_path().c_str());
  return kExitExpected;
}

}  // namespace

Command AddPatternCommand(CLI::App* app) {
  auto flags = std::make_shared<PatternFlags>();
  CLI::App* pattern = app->add_subcommand(
      "pattern",
      "Compare the MID-360 scan patterns (Livox's table, the procedural model, a table of yours)");
  pattern->add_option("--out", flags->out, "Output folder")->required();
  pattern->add_flag("--overwrite", flags->overwrite, "Replace an earlier pattern folder");
  pattern->add_option("--frames", flags->report.frames, "Frames for the accumulated statistics")
      ->capture_default_str();
  pattern->add_option("--table", flags->report.table,
                      "A Livox scan table (CSV Time/s,Azimuth/deg,Zenith/deg) to compare too");
  return {pattern, [flags] { return Pattern(*flags); }};
}

}  // namespace trav::scenarios::cli
