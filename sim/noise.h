#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "common/enum_names.h"

namespace trav::sim {

/// Value and gradient of a 2-D noise field.
struct NoiseSample {
  double value{0.0};
  Eigen::Vector2d gradient{Eigen::Vector2d::Zero()};
};

/// Seeded 2-D Perlin gradient noise (improved Perlin: quintic fade, 8 gradient directions) with its
/// analytic gradient, in [-1, 1] roughly. Written here rather than taken from a library because the
/// terrain must be bit-identical for a seed on every platform, and Debian's noise libraries
/// (libnoise) do not return derivatives, which the derivative-warped "Swiss" family needs.
class PerlinNoise {
 public:
  explicit PerlinNoise(std::uint64_t seed);

  /// Noise and gradient at p (in lattice units).
  NoiseSample Sample(const Eigen::Vector2d& p) const;

 private:
  std::array<std::uint8_t, 512> permutation_{};
};

/// Fractal families of the EPFL procedural terrain generator.
enum class FractalFamily {
  kFbm,      ///< fractional Brownian motion: sum of octaves
  kRidged,   ///< sum of (1 - |n|): sharp ridges
  kBillowy,  ///< sum of |n|: rounded hills and creases
  kSwiss,    ///< ridged noise warped by the running sum of derivatives (erosion-like valleys)
};

/// The names of FractalFamily's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<FractalFamily>, 4> kFractalFamilyNames{
    {{FractalFamily::kFbm, "fbm"},
     {FractalFamily::kRidged, "ridged"},
     {FractalFamily::kBillowy, "billowy"},
     {FractalFamily::kSwiss, "swiss"}}};
constexpr const auto& EnumNames(FractalFamily) { return kFractalFamilyNames; }

/// Parameters of a fractal noise field; lengths in lattice units of the base octave.
struct FractalParams {
  FractalFamily family{FractalFamily::kFbm};
  int octaves{5};          ///< number of octaves, >= 1
  double lacunarity{2.0};  ///< frequency ratio between octaves, > 1
  double gain{0.5};        ///< amplitude ratio between octaves, in (0, 1)
  double warp{0.0};        ///< domain warping strength (kFbm/kRidged/kBillowy: offset by a second
                           ///< noise field; kSwiss: derivative warp), >= 0
};

/// A fractal noise field over the plane built from one seeded Perlin lattice.
class FractalNoise {
 public:
  FractalNoise(std::uint64_t seed, const FractalParams& params);

  /// Field value at p (lattice units of the base octave); unnormalised.
  double Evaluate(const Eigen::Vector2d& p) const;

 private:
  double Octaves(const Eigen::Vector2d& p) const;
  PerlinNoise noise_;
  PerlinNoise warp_x_;
  PerlinNoise warp_y_;
  FractalParams params_;
};

}  // namespace trav::sim
