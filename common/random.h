#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace trav::common {

/// Seeded random numbers that are bit-identical on every platform and standard library: the engine
/// (std::mt19937_64) is fully specified by the C++ standard, but std::*_distribution are not, so
/// the transforms to uniform reals and integers are written here.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  /// Uniform real in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

  /// Uniform real in [low, high).
  double Uniform(double low, double high) { return low + (high - low) * Uniform(); }

  /// Uniform integer in [0, n), n > 0 (rejection sampling, no modulo bias).
  std::uint64_t UniformIndex(std::uint64_t n) {
    const std::uint64_t limit = ~std::uint64_t{0} - (~std::uint64_t{0} % n);
    std::uint64_t value = engine_();
    while (value >= limit) value = engine_();
    return value % n;
  }

  /// Standard normal draw (Box-Muller: each pair of uniform draws gives two values; the second
  /// is returned by the next call).
  double Normal() {
    if (has_spare_normal_) {
      has_spare_normal_ = false;
      return spare_normal_;
    }
    const double u1 = 1.0 - Uniform();  // in (0, 1]
    const double u2 = Uniform();
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_normal_ = radius * std::sin(2.0 * M_PI * u2);
    has_spare_normal_ = true;
    return radius * std::cos(2.0 * M_PI * u2);
  }

  /// True with probability p.
  bool Bernoulli(double p) { return Uniform() < p; }

  /// Raw 64-bit draw (for deriving child seeds).
  std::uint64_t Next() { return engine_(); }

 private:
  std::mt19937_64 engine_;
  double spare_normal_{0.0};
  bool has_spare_normal_{false};
};

}  // namespace trav::common
