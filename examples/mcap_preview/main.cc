// Reads a trav run's run.mcap and draws its end from above, 0.05 m per pixel over the last map: the
// map's traversability (green 0 to red 1, unknown grey), the last LiDAR frame (black dots), the
// robot's track from /tf (blue), the last A* path (white), optimised trajectory (orange) and MPC
// horizon (magenta), the movers (orange discs) and the goal (green ring). Shows how to consume the
// file from C++: the MCAP reader, the Foxglove JSON messages, base64 data.
// Usage: mcap_preview RUN.mcap OUT.png
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <mcap/reader.hpp>
#include <nlohmann/json.hpp>

#include "renders/image.h"
#include "renders/overlay.h"

namespace {

using nlohmann::json;

std::vector<std::uint8_t> DecodeBase64(const std::string& text) {
  static const std::string kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<std::uint8_t> bytes;
  std::uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<std::uint32_t>(kAlphabet.find(c));
    count += 6;
    if (count >= 8) {
      count -= 8;
      bytes.push_back(static_cast<std::uint8_t>((bits >> count) & 0xff));
    }
  }
  return bytes;
}

float FloatAt(const std::vector<std::uint8_t>& data, std::size_t offset) {
  float value;
  std::memcpy(&value, &data[offset], sizeof(value));
  return value;
}

// The picture: world (x, y) to pixels, +y up.
struct Canvas {
  trav::renders::Image image;
  Eigen::Vector2d corner_W;  // lower-left corner [m]
  double metres_per_pixel{0.05};

  bool Pixel(const Eigen::Vector2d& p_W, int* x, int* y) const {
    *x = static_cast<int>(std::floor((p_W.x() - corner_W.x()) / metres_per_pixel));
    *y = image.height - 1 -
         static_cast<int>(std::floor((p_W.y() - corner_W.y()) / metres_per_pixel));
    return *x >= 0 && *y >= 0 && *x < image.width && *y < image.height;
  }
  void Set(int x, int y, const Eigen::Vector3f& rgb) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    std::uint8_t* pixel = image.rgb.data() + 3 * (static_cast<std::size_t>(y) * image.width + x);
    for (int c = 0; c < 3; ++c) pixel[c] = static_cast<std::uint8_t>(255.0f * rgb[c]);
  }
  void Dot(const Eigen::Vector2d& p_W, int radius, const Eigen::Vector3f& rgb) {
    int x, y;
    Pixel(p_W, &x, &y);
    for (int dy = -radius; dy <= radius; ++dy) {
      for (int dx = -radius; dx <= radius; ++dx) {
        if (dx * dx + dy * dy <= radius * radius) Set(x + dx, y + dy, rgb);
      }
    }
  }
  void Line(const std::vector<Eigen::Vector2d>& points_W, int width, const Eigen::Vector3f& rgb) {
    for (std::size_t i = 1; i < points_W.size(); ++i) {
      const double length = (points_W[i] - points_W[i - 1]).norm();
      const int steps = std::max(1, static_cast<int>(length / (0.5 * metres_per_pixel)));
      for (int k = 0; k <= steps; ++k) {
        Dot(points_W[i - 1] + (points_W[i] - points_W[i - 1]) * (double(k) / steps), width, rgb);
      }
    }
  }
};

// The points of the first line strip of a foxglove.SceneUpdate.
std::vector<Eigen::Vector2d> LinePoints(const json& update) {
  std::vector<Eigen::Vector2d> points;
  for (const json& entity : update.at("entities")) {
    for (const json& line : entity.at("lines")) {
      for (const json& p : line.at("points")) points.emplace_back(p.at("x"), p.at("y"));
    }
  }
  return points;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: mcap_preview RUN.mcap OUT.png\n");
    return 2;
  }
  mcap::McapReader reader;
  if (const mcap::Status opened = reader.open(argv[1]); !opened.ok()) {
    std::fprintf(stderr, "mcap_preview: %s: %s\n", argv[1], opened.message.c_str());
    return 2;
  }
  // the last message of each topic, and the robot's track
  std::map<std::string, json> last;
  std::vector<Eigen::Vector2d> track_W;
  double robot_z = 0.0;
  for (const mcap::MessageView& view : reader.readMessages()) {
    const auto* text = reinterpret_cast<const char*>(view.message.data);
    json message = json::parse(text, text + view.message.dataSize);
    if (view.channel->topic == "/tf") {
      const json& t = message.at("transforms").at(0).at("translation");
      track_W.emplace_back(t.at("x"), t.at("y"));
      robot_z = t.at("z");
    }
    last[view.channel->topic] = std::move(message);
  }
  reader.close();
  if (last.count("/map") == 0) {
    std::fprintf(stderr, "mcap_preview: %s holds no /map\n", argv[1]);
    return 2;
  }

  // the map: its grid, one pixel every 0.05 m
  const json& grid = last["/map"];
  const std::vector<std::uint8_t> cells = DecodeBase64(grid.at("data"));
  const int columns = grid.at("column_count");
  const int cell_stride = grid.at("cell_stride");
  const int rows =
      static_cast<int>(cells.size() / (static_cast<std::size_t>(cell_stride) * columns));
  const double cell_m = grid.at("cell_size").at("x");
  int offset = -1;
  for (const json& field : grid.at("fields")) {
    if (field.at("name") == "traversability") offset = field.at("offset");
  }
  Canvas canvas;
  canvas.corner_W = Eigen::Vector2d(grid.at("pose").at("position").at("x"),
                                    grid.at("pose").at("position").at("y"));
  canvas.image.width = static_cast<int>(std::lround(columns * cell_m / canvas.metres_per_pixel));
  canvas.image.height = static_cast<int>(std::lround(rows * cell_m / canvas.metres_per_pixel));
  canvas.image.rgb.assign(static_cast<std::size_t>(canvas.image.width) * canvas.image.height * 3,
                          0);
  for (int y = 0; y < canvas.image.height; ++y) {
    for (int x = 0; x < canvas.image.width; ++x) {
      const int ix = static_cast<int>(x * canvas.metres_per_pixel / cell_m);
      const int iy =
          static_cast<int>((canvas.image.height - 1 - y) * canvas.metres_per_pixel / cell_m);
      const float cost =
          FloatAt(cells, (static_cast<std::size_t>(iy) * columns + ix) * cell_stride + offset);
      canvas.Set(x, y,
                 std::isnan(cost) ? Eigen::Vector3f(0.5f, 0.5f, 0.5f)
                                  : trav::renders::TraversabilityColor(cost, 0.0f, 1.0f));
    }
  }
  // the last LiDAR frame up to 1 m above the robot's base (tree crowns left out): x, y, z float32
  // at offsets 0, 4, 8
  if (last.count("/lidar/points") > 0) {
    const json& cloud = last["/lidar/points"];
    const std::vector<std::uint8_t> points = DecodeBase64(cloud.at("data"));
    const std::size_t stride = cloud.at("point_stride");
    for (std::size_t i = 0; i + stride <= points.size(); i += stride) {
      int x, y;
      if (FloatAt(points, i + 8) > robot_z + 1.0) continue;
      if (canvas.Pixel(Eigen::Vector2d(FloatAt(points, i), FloatAt(points, i + 4)), &x, &y)) {
        canvas.Set(x, y, Eigen::Vector3f(0.1f, 0.1f, 0.1f));
      }
    }
  }
  canvas.Line(track_W, 1, Eigen::Vector3f(0.1f, 0.3f, 0.9f));
  if (last.count("/planner/path") > 0) canvas.Line(LinePoints(last["/planner/path"]), 1, {1, 1, 1});
  if (last.count("/planner/trajectory") > 0) {
    canvas.Line(LinePoints(last["/planner/trajectory"]), 2, Eigen::Vector3f(1.0f, 0.55f, 0.0f));
  }
  if (last.count("/controller/horizon") > 0) {
    canvas.Line(LinePoints(last["/controller/horizon"]), 1, Eigen::Vector3f(0.9f, 0.1f, 0.9f));
  }
  if (last.count("/movers/true") > 0) {
    for (const json& cylinder : last["/movers/true"].at("entities").at(0).at("cylinders")) {
      const json& p = cylinder.at("pose").at("position");
      canvas.Dot(Eigen::Vector2d(p.at("x"), p.at("y")), 6, Eigen::Vector3f(0.95f, 0.55f, 0.1f));
    }
  }
  for (const json& sphere : last["/goal"].at("entities").at(0).at("spheres")) {
    const json& p = sphere.at("pose").at("position");
    canvas.Dot(Eigen::Vector2d(p.at("x"), p.at("y")), 8, Eigen::Vector3f(0.1f, 0.8f, 0.2f));
    canvas.Dot(Eigen::Vector2d(p.at("x"), p.at("y")), 5, Eigen::Vector3f(1.0f, 1.0f, 1.0f));
  }
  if (!track_W.empty()) canvas.Dot(track_W.back(), 6, Eigen::Vector3f(0.0f, 0.0f, 0.0f));
  trav::renders::WritePng(argv[2], canvas.image);
  std::printf("mcap_preview: %s (%d x %d pixels, %zu topics)\n", argv[2], canvas.image.width,
              canvas.image.height, last.size());
  return 0;
}
