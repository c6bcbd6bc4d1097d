#include "renders/map_panel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <fmt/format.h>

#include "renders/overlay.h"

namespace trav::renders {
namespace {

// World to pixel for a square view: +x right, +y up.
struct View {
  Eigen::Vector2d corner_W;  // bottom-left [m]
  double pixels_per_m;
  int size_px;

  Eigen::Vector2d ToPixel(const Eigen::Vector2d& p_W) const {
    const Eigen::Vector2d q = (p_W - corner_W) * pixels_per_m;
    return {q.x(), size_px - q.y()};
  }
  Eigen::Vector2d ToWorld(double px, double py) const {
    return corner_W + Eigen::Vector2d(px, size_px - py) / pixels_per_m;
  }
};

void Put(Image* image, int x, int y, const Eigen::Vector3i& rgb) {
  if (x < 0 || y < 0 || x >= image->width || y >= image->height) return;
  std::uint8_t* p = image->rgb.data() + 3 * (y * image->width + x);
  for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint8_t>(std::clamp(rgb[c], 0, 255));
}

// A square brush of `width` pixels stamped along the segment a-b.
void Segment(Image* image, const Eigen::Vector2d& a, const Eigen::Vector2d& b, int width,
             const Eigen::Vector3i& rgb) {
  const int steps = static_cast<int>(std::ceil((b - a).norm())) + 1;
  const int low = -(width - 1) / 2, high = width / 2;
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(k) / steps);
    for (int dx = low; dx <= high; ++dx) {
      for (int dy = low; dy <= high; ++dy) {
        Put(image, static_cast<int>(std::floor(p.x())) + dx,
            static_cast<int>(std::floor(p.y())) + dy, rgb);
      }
    }
  }
}

// A disc of radius `r` [pixels] at `c`, filled or as a ring.
void Disc(Image* image, const Eigen::Vector2d& c, double r, bool filled,
          const Eigen::Vector3i& rgb) {
  const int reach = static_cast<int>(std::ceil(r));
  for (int dx = -reach; dx <= reach; ++dx) {
    for (int dy = -reach; dy <= reach; ++dy) {
      const double d = std::hypot(dx, dy);
      if (d > r || (!filled && d < r - 1.5)) continue;
      Put(image, static_cast<int>(std::floor(c.x())) + dx, static_cast<int>(std::floor(c.y())) + dy,
          rgb);
    }
  }
}

// A filled rotated rectangle: the pixels whose centres lie inside it, outlined in white, with a
// white tick from its centre to its front.
void Box(Image* image, const View& view, const PanelBox& box) {
  const Eigen::Rotation2Dd R_WB(box.yaw_rad);
  const double reach_m = box.half_extents_m.norm();
  const Eigen::Vector2d low = view.ToPixel(box.centre_W + Eigen::Vector2d(-reach_m, reach_m));
  const Eigen::Vector2d high = view.ToPixel(box.centre_W + Eigen::Vector2d(reach_m, -reach_m));
  const double edge_m = 1.5 / view.pixels_per_m;  // the outline: 1.5 pixels wide
  for (int py = static_cast<int>(std::floor(low.y())); py <= static_cast<int>(high.y()); ++py) {
    for (int px = static_cast<int>(std::floor(low.x())); px <= static_cast<int>(high.x()); ++px) {
      const Eigen::Vector2d p_B =
          R_WB.inverse() * (view.ToWorld(px + 0.5, py + 0.5) - box.centre_W);
      const Eigen::Vector2d margin = box.half_extents_m - p_B.cwiseAbs();
      if (margin.minCoeff() < 0.0) continue;
      Put(image, px, py, margin.minCoeff() < edge_m ? Eigen::Vector3i(255, 255, 255) : box.rgb);
    }
  }
  Segment(image, view.ToPixel(box.centre_W),
          view.ToPixel(box.centre_W + R_WB * Eigen::Vector2d(box.half_extents_m.x(), 0.0)), 2,
          Eigen::Vector3i(255, 255, 255));
}

}  // namespace

Image DrawMapPanel(const common::GridLayers& map, const Eigen::MatrixXf& layer,
                   const Eigen::Vector2d& centre_W, double span_m, int size_px,
                   const PanelOverlay& overlay) {
  Image image;
  image.width = image.height = size_px;
  image.rgb.assign(static_cast<std::size_t>(3 * size_px * size_px), 0);
  const View view{centre_W - Eigen::Vector2d::Constant(0.5 * span_m), size_px / span_m, size_px};
  const common::GridGeometry& g = map.geometry();
  const Eigen::Vector3i unknown(128, 128, 128);
  for (int py = 0; py < size_px; ++py) {
    for (int px = 0; px < size_px; ++px) {
      const std::optional<Eigen::Vector2i> cell = g.CellIndex(view.ToWorld(px + 0.5, py + 0.5));
      const float value = cell ? layer(cell->x(), cell->y()) : NAN;
      if (std::isnan(value)) {
        Put(&image, px, py, unknown);
      } else {
        const Eigen::Vector3f c = TraversabilityColor(value, 0.0f, 1.0f);
        Put(&image, px, py, (255.0f * c).cast<int>());
      }
    }
  }
  for (const PanelPath& path : overlay.paths) {
    for (std::size_t i = 1; i < path.points_W.size(); ++i) {
      Segment(&image, view.ToPixel(path.points_W[i - 1]), view.ToPixel(path.points_W[i]),
              path.width_px, path.rgb);
    }
  }
  for (const Eigen::Vector2d& p_W : overlay.points_W) {
    const Eigen::Vector2d p = view.ToPixel(p_W);
    Put(&image, static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())),
        overlay.points_rgb);
  }
  for (const PanelDisc& disc : overlay.discs) {
    Disc(&image, view.ToPixel(disc.centre_W), std::max(1.5, disc.radius_m * view.pixels_per_m),
         disc.filled, disc.rgb);
  }
  for (const PanelBox& box : overlay.boxes) Box(&image, view, box);
  return image;
}

double ScaleBarLength(double max_m) {
  double length = std::pow(10.0, std::floor(std::log10(max_m)));
  for (const double factor : {5.0, 2.0}) {
    if (factor * length <= max_m) return factor * length;
  }
  return length;
}

Panel LayoutMapPanel(const Image& map, double span_m, int height_px,
                     const std::vector<LegendEntry>& legend, const std::string& info, int line_px,
                     const std::function<int(const std::string&)>& text_width_px) {
  if (height_px < map.height) {
    throw std::invalid_argument("LayoutMapPanel: the panel is lower than its map");
  }
  Panel panel;
  Image& image = panel.image;
  image.width = map.width;
  image.height = height_px;
  image.rgb.resize(static_cast<std::size_t>(3 * image.width * image.height));
  std::copy(map.rgb.begin(), map.rgb.end(), image.rgb.begin());
  const Eigen::Vector3i dark(28, 30, 36), white(255, 255, 255);
  FillRect(&image, 0, map.height, image.width, image.height, dark);
  const int margin = std::max(4, image.width / 40);
  auto text = [&](const std::string& s, int x, int y) {
    panel.texts.push_back({s, Eigen::Vector2i(x, y), Eigen::Vector3f::Ones()});
  };
  int y = map.height + margin / 2;
  // the cost scale: a colour bar with ticks at 0, 0.5 and 1
  text("traversability cost", margin, y);
  y += line_px;
  const int bar_left = margin, bar_right = image.width - margin, bar_height = line_px / 2 + 2;
  for (int x = bar_left; x < bar_right; ++x) {
    const float value =
        static_cast<float>(x - bar_left) / static_cast<float>(bar_right - 1 - bar_left);
    FillRect(&image, x, y, x + 1, y + bar_height,
             (255.0f * TraversabilityColor(value, 0.0f, 1.0f)).cast<int>());
  }
  for (int k = 0; k <= 2; ++k) {
    const int x = bar_left + k * (bar_right - 1 - bar_left) / 2;
    FillRect(&image, x, y + bar_height, x + 1, y + bar_height + 4, white);
  }
  y += bar_height + 4;
  text("0 free", bar_left, y);
  text("0.5", (bar_left + bar_right) / 2 - text_width_px("0.5") / 2, y);
  text("1 lethal", bar_right - text_width_px("1 lethal"), y);
  y += line_px + margin / 2;
  // unknown cells, and the scale bar
  FillRect(&image, margin, y + 2, margin + line_px, y + line_px - 2,
           Eigen::Vector3i(128, 128, 128));
  text("unknown", margin + line_px + margin / 2, y);
  const double pixels_per_m = map.width / span_m;
  const double bar_m = ScaleBarLength(image.width / 3.0 / pixels_per_m);
  const int scale_right = image.width - margin;
  const int scale_left = scale_right - static_cast<int>(std::lround(bar_m * pixels_per_m));
  FillRect(&image, scale_left, y + line_px / 2 - 1, scale_right, y + line_px / 2 + 2, white);
  FillRect(&image, scale_left, y + 2, scale_left + 2, y + line_px - 2, white);
  FillRect(&image, scale_right - 2, y + 2, scale_right, y + line_px - 2, white);
  const std::string bar_label = fmt::format("{:g} m", bar_m);
  text(bar_label, scale_left - margin - text_width_px(bar_label), y);
  y += line_px + margin / 2;
  // the legend, in two columns
  const int column_width = (image.width - 2 * margin) / 2;
  for (std::size_t i = 0; i < legend.size(); ++i) {
    const LegendEntry& entry = legend[i];
    const int x = margin + static_cast<int>(i % 2) * column_width;
    const int row = y + static_cast<int>(i / 2) * line_px;
    const Eigen::Vector2d mid(x + line_px / 2.0, row + line_px / 2.0);
    switch (entry.symbol) {
      case LegendEntry::Symbol::kLine:
        FillRect(&image, x, row + line_px / 2 - 1, x + line_px, row + line_px / 2 + 2, entry.rgb);
        break;
      case LegendEntry::Symbol::kDisc:
        Disc(&image, mid, line_px / 3.0, true, entry.rgb);
        break;
      case LegendEntry::Symbol::kDots:
        for (int k = 0; k < 9; ++k) {
          const int dx = 2 + (k * 7) % (line_px - 3), dy = 3 + (k * 5) % (line_px - 5);
          FillRect(&image, x + dx, row + dy, x + dx + 2, row + dy + 2, entry.rgb);
        }
        break;
      case LegendEntry::Symbol::kBox:  // outlined in white, as Box draws a footprint
        FillRect(&image, x + line_px / 4 - 1, row + line_px / 4 - 1, x + 3 * line_px / 4 + 1,
                 row + 3 * line_px / 4 + 1, white);
        FillRect(&image, x + line_px / 4, row + line_px / 4, x + 3 * line_px / 4,
                 row + 3 * line_px / 4, entry.rgb);
        break;
    }
    text(entry.label, x + line_px + margin / 2, row);
  }
  y += static_cast<int>((legend.size() + 1) / 2) * line_px + margin / 2;
  text(info, margin, y);
  return panel;
}

}  // namespace trav::renders
