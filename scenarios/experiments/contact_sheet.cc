#include "scenarios/experiments/contact_sheet.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <Eigen/Core>

#include "renders/image.h"
#include "scenarios/run/output_folder.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

constexpr int kFramePixels = 4;
constexpr int kMaxColumns = 8;
// Runs tiled in contact_sheet.png, at most (40 rows: 1664 x 8320 pixels); the HTML lists all.
constexpr std::size_t kMaxTiledRuns = 320;
// Map images larger than this are not read (a run's map_paths.png is 800 x 800).
constexpr std::size_t kMaxImagePixels = 16'000'000;

const Eigen::Vector3i kSuccessRgb(40, 170, 70), kFailureRgb(210, 40, 40), kNoImageRgb(90, 90, 90);

// `text` with HTML's special characters escaped (ids and parameter values come from files).
std::string Html(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      case '\'':
        escaped += "&#39;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

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

// Fills the rectangle of columns [x0, x1) and rows [y0, y1) of `image`.
void Fill(renders::Image* image, int x0, int y0, int x1, int y1, const Eigen::Vector3i& rgb) {
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      std::uint8_t* p = image->rgb.data() + 3 * (static_cast<std::size_t>(y) * image->width + x);
      for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint8_t>(rgb[c]);
    }
  }
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

  const std::size_t tiled = std::min(results.size(), kMaxTiledRuns);
  const int columns = std::min(kMaxColumns, std::max(1, static_cast<int>(tiled)));
  const int rows = (static_cast<int>(tiled) + columns - 1) / columns;
  const int cell = kThumbnailPixels + 2 * kFramePixels;
  renders::Image sheet;
  sheet.width = columns * cell;
  sheet.height = rows * cell;
  sheet.rgb.assign(static_cast<std::size_t>(3 * sheet.width * sheet.height), 255);
  bool any_image = false;
  std::error_code error;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const BatchResult& run = results[i];
    const fs::path run_folder = folder / "runs" / run.id;
    const std::string url = "runs/" + UrlPath(run.id) + "/";
    // a thumbnail from the run's map, if it has one that reads (read only for tiled runs)
    const bool has_map = fs::is_regular_file(run_folder / "map_paths.png", error);
    std::optional<renders::Image> thumbnail;
    if (has_map && i < tiled) {
      try {
        thumbnail = renders::Downscale(
            renders::ReadPngRgb((run_folder / "map_paths.png").string(), kMaxImagePixels),
            kThumbnailPixels, kThumbnailPixels);
      } catch (const std::runtime_error&) {
        thumbnail.reset();  // a damaged image: the cell says "no image"
      }
    }
    const bool has_image = i < tiled ? thumbnail.has_value() : has_map;
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
           << "px;max-height:" << kThumbnailPixels << "px\" alt=\"" << Html(run.id) << "\">";
    } else {
      html << "<div class=\"none\">no image</div>";
    }
    html << "</a><br><b>" << Html(run.id) << "</b><br>";
    for (const auto& [label, value] : run.parameters) {
      html << Html(label) << " = " << Html(value) << "<br>";
    }
    html << Html(run.outcome) << "</div>\n";

    // the PNG: the thumbnail centred in its cell, in a frame of the outcome's colour
    if (i >= tiled) continue;
    const int x0 = static_cast<int>(i % columns) * cell, y0 = static_cast<int>(i / columns) * cell;
    Fill(&sheet, x0, y0, x0 + cell, y0 + cell, run.success ? kSuccessRgb : kFailureRgb);
    Fill(&sheet, x0 + kFramePixels, y0 + kFramePixels, x0 + cell - kFramePixels,
         y0 + cell - kFramePixels, kNoImageRgb);
    if (!thumbnail) continue;
    const int left = x0 + kFramePixels + (kThumbnailPixels - thumbnail->width) / 2;
    const int top = y0 + kFramePixels + (kThumbnailPixels - thumbnail->height) / 2;
    for (int y = 0; y < thumbnail->height; ++y) {
      std::copy_n(thumbnail->Pixel(0, y), 3 * thumbnail->width,
                  sheet.rgb.data() + 3 * (static_cast<std::size_t>(top + y) * sheet.width + left));
    }
    any_image = true;
  }
  html << "</div>\n</body></html>\n";
  WriteTextFileAtomically((folder / "contact_sheet.html").string(), html.str());
  written.push_back("contact_sheet.html");
  if (any_image) {
    WriteFileAtomically(
        (folder / "contact_sheet.png").string(),
        [&sheet](const std::string& partial) { renders::WritePng(partial, sheet); });
    written.push_back("contact_sheet.png");
  }
  return written;
}

}  // namespace trav::scenarios
