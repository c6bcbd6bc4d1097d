#include "scenarios/run/thumbnail_sheet.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "renders/image.h"
#include "scenarios/run/output_folder.h"

namespace trav::scenarios {
namespace {

// Images larger than this are not read (a run's map_paths.png is 800 x 800).
constexpr std::size_t kMaxImagePixels = 16'000'000;
const Eigen::Vector3i kNoImageRgb(90, 90, 90);

// The image at `path` shrunk to fit `size` x `size`, or nothing if it cannot be read.
std::optional<renders::Image> Thumbnail(const std::string& path, int size) {
  if (path.empty()) return std::nullopt;
  try {
    return renders::Downscale(renders::ReadPngRgb(path, kMaxImagePixels), size, size);
  } catch (const std::runtime_error&) {
    return std::nullopt;  // missing or damaged: a grey tile
  }
}

}  // namespace

std::vector<bool> WriteThumbnailSheet(const std::string& path, const std::vector<SheetTile>& tiles,
                                      int columns, int tile_px, int frame_px) {
  std::vector<bool> readable(tiles.size(), false);
  if (tiles.empty()) return readable;
  columns = std::clamp(columns, 1, static_cast<int>(tiles.size()));
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  const int cell = tile_px + 2 * frame_px;
  renders::Image sheet;
  sheet.width = columns * cell;
  sheet.height = rows * cell;
  sheet.rgb.assign(static_cast<std::size_t>(3 * sheet.width * sheet.height), 255);
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const int x0 = static_cast<int>(i % columns) * cell, y0 = static_cast<int>(i / columns) * cell;
    renders::FillRect(&sheet, x0, y0, x0 + cell, y0 + cell, tiles[i].frame_rgb);
    renders::FillRect(&sheet, x0 + frame_px, y0 + frame_px, x0 + cell - frame_px,
                      y0 + cell - frame_px, kNoImageRgb);
    const std::optional<renders::Image> thumbnail = Thumbnail(tiles[i].image_path, tile_px);
    if (!thumbnail) continue;
    readable[i] = true;
    const int left = x0 + frame_px + (tile_px - thumbnail->width) / 2;
    const int top = y0 + frame_px + (tile_px - thumbnail->height) / 2;
    for (int y = 0; y < thumbnail->height; ++y) {
      std::copy_n(thumbnail->Pixel(0, y), 3 * thumbnail->width,
                  sheet.rgb.data() + 3 * (static_cast<std::size_t>(top + y) * sheet.width + left));
    }
  }
  if (std::find(readable.begin(), readable.end(), true) != readable.end()) {
    WriteFileAtomically(
        path, [&sheet](const std::string& partial) { renders::WritePng(partial, sheet); });
  }
  return readable;
}

}  // namespace trav::scenarios
