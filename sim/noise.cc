#include "sim/noise.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/random.h"

namespace trav::sim {
namespace {

double Fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
double FadeDerivative(double t) { return 30.0 * t * t * (t * (t - 2.0) + 1.0); }

// Gradient directions: the 4 axes and the 4 diagonals.
constexpr double kDiagonal = 0.70710678118654752;
constexpr std::array<std::array<double, 2>, 8> kGradients = {{{1.0, 0.0},
                                                              {-1.0, 0.0},
                                                              {0.0, 1.0},
                                                              {0.0, -1.0},
                                                              {kDiagonal, kDiagonal},
                                                              {-kDiagonal, kDiagonal},
                                                              {kDiagonal, -kDiagonal},
                                                              {-kDiagonal, -kDiagonal}}};

}  // namespace

PerlinNoise::PerlinNoise(std::uint64_t seed) {
  // Fisher-Yates shuffle of 0..255 with the platform-independent generator, duplicated to 512.
  std::array<std::uint8_t, 256> values{};
  std::iota(values.begin(), values.end(), 0);
  common::Random random(seed);
  for (int i = 255; i > 0; --i) {
    std::swap(values[i], values[random.UniformIndex(static_cast<std::uint64_t>(i) + 1)]);
  }
  for (int i = 0; i < 512; ++i) permutation_[i] = values[i & 255];
}

NoiseSample PerlinNoise::Sample(const Eigen::Vector2d& p) const {
  const double fx = std::floor(p.x());
  const double fy = std::floor(p.y());
  const int ix = static_cast<int>(static_cast<long long>(fx) & 255);
  const int iy = static_cast<int>(static_cast<long long>(fy) & 255);
  const double tx = p.x() - fx;
  const double ty = p.y() - fy;

  // dot products of the corner gradients with the offsets to p
  auto corner = [&](int cx, int cy, double dx, double dy, Eigen::Vector2d* g) {
    const auto& gradient = kGradients[permutation_[permutation_[ix + cx] + iy + cy] & 7];
    *g = Eigen::Vector2d(gradient[0], gradient[1]);
    return gradient[0] * dx + gradient[1] * dy;
  };
  Eigen::Vector2d g00, g10, g01, g11;
  const double n00 = corner(0, 0, tx, ty, &g00);
  const double n10 = corner(1, 0, tx - 1.0, ty, &g10);
  const double n01 = corner(0, 1, tx, ty - 1.0, &g01);
  const double n11 = corner(1, 1, tx - 1.0, ty - 1.0, &g11);

  // quintic interpolation and its derivative
  const double u = Fade(tx);
  const double v = Fade(ty);
  const double du = FadeDerivative(tx);
  const double dv = FadeDerivative(ty);
  const double k0 = n00;
  const double k1 = n10 - n00;
  const double k2 = n01 - n00;
  const double k3 = n00 - n10 - n01 + n11;

  NoiseSample sample;
  sample.value = k0 + k1 * u + k2 * v + k3 * u * v;
  sample.gradient = g00 + u * (g10 - g00) + v * (g01 - g00) + u * v * (g00 - g10 - g01 + g11) +
                    Eigen::Vector2d(du * (k1 + k3 * v), dv * (k2 + k3 * u));
  return sample;
}

FractalNoise::FractalNoise(std::uint64_t seed, const FractalParams& params)
    : noise_(seed),
      warp_x_(seed ^ 0x9e3779b97f4a7c15ULL),
      warp_y_(seed ^ 0xc2b2ae3d27d4eb4fULL),
      params_(params) {}

double FractalNoise::Evaluate(const Eigen::Vector2d& p) const {
  if (params_.family == FractalFamily::kSwiss || params_.warp == 0.0) return Octaves(p);
  // domain warping: offset the lookup by two further low-frequency noise fields
  const Eigen::Vector2d offset(warp_x_.Sample(p + Eigen::Vector2d(5.2, 1.3)).value,
                               warp_y_.Sample(p + Eigen::Vector2d(1.7, 9.2)).value);
  return Octaves(p + params_.warp * offset);
}

double FractalNoise::Octaves(const Eigen::Vector2d& p) const {
  double sum = 0.0;
  double frequency = 1.0;
  double amplitude = 1.0;
  Eigen::Vector2d derivative_sum = Eigen::Vector2d::Zero();
  for (int octave = 0; octave < params_.octaves; ++octave) {
    // each octave is shifted so that lattice points of different octaves do not line up
    const Eigen::Vector2d shift(17.31 * octave, 29.17 * octave);
    switch (params_.family) {
      case FractalFamily::kFbm:
        sum += amplitude * noise_.Sample(p * frequency + shift).value;
        amplitude *= params_.gain;
        break;
      case FractalFamily::kRidged:
        sum += amplitude * (1.0 - std::abs(noise_.Sample(p * frequency + shift).value));
        amplitude *= params_.gain;
        break;
      case FractalFamily::kBillowy:
        sum += amplitude * std::abs(noise_.Sample(p * frequency + shift).value);
        amplitude *= params_.gain;
        break;
      case FractalFamily::kSwiss: {
        // ridged noise sampled at a position warped by the accumulated derivatives; amplitudes of
        // higher octaves shrink where the sum is low (valleys stay smooth)
        const NoiseSample n =
            noise_.Sample((p + params_.warp * derivative_sum) * frequency + shift);
        sum += amplitude * (1.0 - std::abs(n.value));
        derivative_sum += amplitude * n.gradient * -n.value;
        amplitude *= params_.gain * std::clamp(sum, 0.0, 1.0);
        break;
      }
    }
    frequency *= params_.lacunarity;
  }
  return sum;
}

}  // namespace trav::sim
