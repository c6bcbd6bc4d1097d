#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace trav::scenarios {

/// A tile of a thumbnail sheet: an image file shown in a frame of a colour.
struct SheetTile {
  std::string image_path;  ///< a PNG; empty, missing or unreadable: the tile is grey
  Eigen::Vector3i frame_rgb{255, 255, 255};
};

/// Tiles `tiles` into one PNG at `path`, `columns` a row: each image shrunk to fit a square of
/// `tile_px` pixels (box filter, aspect ratio kept) and centred on grey, in a frame of `frame_px`
/// pixels of its colour. Written atomically (WriteFileAtomically), and only when at least one
/// tile's image could be read. Returns, per tile, whether its image could be read (images larger
/// than 16 megapixels are not read).
std::vector<bool> WriteThumbnailSheet(const std::string& path, const std::vector<SheetTile>& tiles,
                                      int columns, int tile_px, int frame_px);

}  // namespace trav::scenarios
