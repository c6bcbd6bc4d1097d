#include "scenarios/experiments/contact_sheet.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>
#include <system_error>

#include <Eigen/Core>

#include "common/text.h"
#include "scenarios/run/output_folder.h"
#include "scenarios/run/thumbnail_sheet.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

constexpr int kFramePixels = 4;
constexpr int kMaxColumns = 8;
// Runs tiled in contact_sheet.png, at most (40 rows: 1664 x 8320 pixels); the HTML lists all.
constexpr std::size_t kMaxTiledRuns = 320;
const Eigen::Vector3i kSuccessRgb(40, 170, 70), kFailureRgb(210, 40, 40);

// A run folder's relative path component, percent-encoded for a URL.
std::string UrlPath(const std::string& text) {
  std::string encoded;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (std::isalnum(byte) || c == '-' || c == '_' || c == '.' || c == '/') {
      encoded += c;
    } else {
      static const char kHex[] = "0123456789ABCDEF";
      encoded += '%';
      encoded += kHex[byte >> 4];
      encoded += kHex[byte & 0xf];
    }
  }
  return encoded;
}

}  // namespace

std::vector<std::string> WriteContactSheet(const std::string& out_dir,
                                           const std::vector<BatchResult>& results) {
  const fs::path folder(out_dir);
  std::vector<std::string> written;
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Contact sheet</title>\n"
       << "<style>body{font-family:sans-serif} .sheet{display:grid;grid-template-columns:"
       << "repeat(auto-fill," << kThumbnailPixels + 20 << "px);gap:8px}"
       << " .run{border:" << kFramePixels << "px solid;padding:4px;font-size:12px}"
       << " .ok{border-color:#28aa46} .failed{border-color:#d22828}"
       << " .none{width:" << kThumbnailPixels << "px;height:" << kThumbnailPixels
       << "px;background:#5a5a5a;color:#fff;display:flex;align-items:center;"
       << "justify-content:center}</style></head><body>\n<h1>Contact sheet</h1>\n"
       << "<p>One cell per run: its final map with the plan and the driven path (map_paths.png); "
       << "green: ended as its scenario expects, red: otherwise. A thumbnail links to the run's "
       << "video when it has one.</p>\n<div class=\"sheet\">\n";

  // the PNG first: it says which maps could be read
  const std::size_t tiled = std::min(results.size(), kMaxTiledRuns);
  std::vector<SheetTile> tiles;
  std::error_code error;
  for (std::size_t i = 0; i < tiled; ++i) {
    const fs::path map = folder / "runs" / results[i].id / "map_paths.png";
    tiles.push_back({fs::is_regular_file(map, error) ? map.string() : std::string(),
                     results[i].success ? kSuccessRgb : kFailureRgb});
  }
  const std::vector<bool> readable = WriteThumbnailSheet(
      (folder / "contact_sheet.png").string(), tiles, kMaxColumns, kThumbnailPixels, kFramePixels);
  const bool any_image = std::find(readable.begin(), readable.end(), true) != readable.end();

  for (std::size_t i = 0; i < results.size(); ++i) {
    const BatchResult& run = results[i];
    const fs::path run_folder = folder / "runs" / run.id;
    const std::string url = "runs/" + UrlPath(run.id) + "/";
    // a map that cannot be read counts as none (runs beyond the PNG's: as it is)
    const bool has_image =
        i < tiled ? readable[i] : fs::is_regular_file(run_folder / "map_paths.png", error);
    const bool has_video = fs::is_regular_file(run_folder / "video.mp4", error);
    // a run that failed to finish has only its record in failed/
    const std::string link = has_video   ? url + "video.mp4"
                             : has_image ? url + "map_paths.png"
                             : fs::is_regular_file(run_folder / "summary.json", error)
                                 ? url + "summary.json"
                                 : "failed/" + UrlPath(run.id) + ".json";
    html << "<div class=\"run " << (run.success ? "ok" : "failed") << "\"><a href=\"" << link
         << "\">";
    if (has_image) {
      html << "<img src=\"" << url << "map_paths.png\" style=\"max-width:" << kThumbnailPixels
           << "px;max-height:" << kThumbnailPixels << "px\" alt=\"" << common::EscapeMarkup(run.id)
           << "\">";
    } else {
      html << "<div class=\"none\">no image</div>";
    }
    html << "</a><br><b>" << common::EscapeMarkup(run.id) << "</b><br>";
    for (const auto& [label, value] : run.parameters) {
      html << common::EscapeMarkup(label) << " = " << common::EscapeMarkup(value) << "<br>";
    }
    html << common::EscapeMarkup(run.outcome) << "</div>\n";
  }
  html << "</div>\n</body></html>\n";
  WriteTextFileAtomically((folder / "contact_sheet.html").string(), html.str());
  written.push_back("contact_sheet.html");
  if (any_image) written.push_back("contact_sheet.png");
  return written;
}

}  // namespace trav::scenarios
