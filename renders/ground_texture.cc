#include "renders/ground_texture.h"

#include <algorithm>
#include <cmath>

namespace trav::renders {
namespace {

// A repeatable pseudo-random value in [0, 1) of integer coordinates (a 32-bit integer hash).
float Hash(int x, int y, std::uint32_t seed) {
  std::uint32_t h = static_cast<std::uint32_t>(x) * 0x8da6b343u ^
                    static_cast<std::uint32_t>(y) * 0xd8163841u ^ seed * 0xcb1ab31fu;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return static_cast<float>(h & 0xffffffu) / static_cast<float>(0x1000000u);
}

// Smooth value noise in [0, 1) with a feature size of one unit of (u, v).
float ValueNoise(double u, double v, std::uint32_t seed) {
  const int x = static_cast<int>(std::floor(u)), y = static_cast<int>(std::floor(v));
  const float fx = static_cast<float>(u - x), fy = static_cast<float>(v - y);
  const float sx = fx * fx * (3.0f - 2.0f * fx), sy = fy * fy * (3.0f - 2.0f * fy);
  const float a = Hash(x, y, seed) + sx * (Hash(x + 1, y, seed) - Hash(x, y, seed));
  const float b = Hash(x, y + 1, seed) + sx * (Hash(x + 1, y + 1, seed) - Hash(x, y + 1, seed));
  return a + sy * (b - a);
}

Eigen::Vector3f Mix(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float t) {
  return a + std::clamp(t, 0.0f, 1.0f) * (b - a);
}

// Smooth step of x from edge0 to edge1.
float Ramp(float x, float edge0, float edge1) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// The colour of ground of `material` at slope `slope_deg`, relative height `rise` in [0, 1] and
// world position (x, y) [m].
Eigen::Vector3f Paint(GroundMaterial material, float slope_deg, float rise, double x, double y) {
  const Eigen::Vector3f grass(0.30f, 0.46f, 0.17f), grass_high(0.42f, 0.54f, 0.22f);
  const Eigen::Vector3f soil(0.42f, 0.33f, 0.22f), rock(0.50f, 0.49f, 0.46f);
  const float patches = ValueNoise(x / 1.7, y / 1.7, 1);  // patches of about a metre
  Eigen::Vector3f colour;
  switch (material) {
    case GroundMaterial::kGrass:
      colour = Mix(grass, grass_high, 0.6f * rise + 0.4f * patches);
      colour = Mix(colour, soil, Ramp(slope_deg, 22.0f, 32.0f));
      colour = Mix(colour, rock, Ramp(slope_deg, 35.0f, 45.0f));
      break;
    case GroundMaterial::kSoil:
      colour = Mix(soil, Eigen::Vector3f(0.52f, 0.43f, 0.30f), 0.5f * rise + 0.5f * patches);
      colour = Mix(colour, rock, Ramp(slope_deg, 20.0f, 35.0f));
      break;
    case GroundMaterial::kRock:
      colour = Mix(rock, Eigen::Vector3f(0.60f, 0.58f, 0.54f), 0.5f * rise + 0.5f * patches);
      break;
    case GroundMaterial::kFloor: {
      const double fx = x - std::floor(x), fy = y - std::floor(y);
      const bool joint = std::min({fx, fy, 1.0 - fx, 1.0 - fy}) < 0.015;
      colour = joint ? Eigen::Vector3f(0.45f, 0.44f, 0.42f)
                     : Mix(Eigen::Vector3f(0.72f, 0.70f, 0.66f),
                           Eigen::Vector3f(0.78f, 0.76f, 0.72f), patches);
      return colour;
    }
  }
  // fine grain: a few per cent of brightness per texel
  return colour * (0.93f + 0.14f * ValueNoise(x / 0.06, y / 0.06, 2));
}

}  // namespace

std::vector<std::uint8_t> GroundTexture(const Eigen::MatrixXf& height_m,
                                        const Eigen::Vector2d& extent_m, GroundMaterial material,
                                        int size) {
  const int nx = static_cast<int>(height_m.rows()), ny = static_cast<int>(height_m.cols());
  const double dx = extent_m.x() / (nx - 1), dy = extent_m.y() / (ny - 1);
  const float low = height_m.minCoeff();
  const float span = std::max(0.5f, height_m.maxCoeff() - low);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(size) * size * 3);
  for (int r = 0; r < size; ++r) {
    const double y = (r + 0.5) / size * extent_m.y();
    const int iy = std::clamp(static_cast<int>(y / dy), 0, ny - 2);
    const float ty = static_cast<float>(std::clamp(y / dy - iy, 0.0, 1.0));
    for (int c = 0; c < size; ++c) {
      const double x = (c + 0.5) / size * extent_m.x();
      const int ix = std::clamp(static_cast<int>(x / dx), 0, nx - 2);
      const float tx = static_cast<float>(std::clamp(x / dx - ix, 0.0, 1.0));
      const float z00 = height_m(ix, iy), z10 = height_m(ix + 1, iy);
      const float z01 = height_m(ix, iy + 1), z11 = height_m(ix + 1, iy + 1);
      const float z = (1 - ty) * ((1 - tx) * z00 + tx * z10) + ty * ((1 - tx) * z01 + tx * z11);
      const float gx = static_cast<float>(((1 - ty) * (z10 - z00) + ty * (z11 - z01)) / dx);
      const float gy = static_cast<float>(((1 - tx) * (z01 - z00) + tx * (z11 - z10)) / dy);
      const float slope_deg = std::atan(std::hypot(gx, gy)) * 180.0f / static_cast<float>(M_PI);
      const Eigen::Vector3f colour = Paint(material, slope_deg, (z - low) / span, x, y);
      std::uint8_t* texel = rgb.data() + 3 * (static_cast<std::size_t>(r) * size + c);
      for (int k = 0; k < 3; ++k) {
        texel[k] = static_cast<std::uint8_t>(std::clamp(255.0f * colour[k], 0.0f, 255.0f));
      }
    }
  }
  return rgb;
}

}  // namespace trav::renders
