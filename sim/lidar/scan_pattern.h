#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace trav::lidar {

/// One ray of a scan pattern, in the sensor frame L (x forward, z up).
struct PatternRay {
  Eigen::Vector3f direction_L{Eigen::Vector3f::UnitX()};  ///< unit vector
  int line{0};                                            ///< laser line (0..3 on the MID-360)
};

/// The direction of every ray a spinning LiDAR fires, by its global index (ray i is fired at
/// i / points_per_second after the sensor started).
class ScanPattern {
 public:
  virtual ~ScanPattern() = default;
  /// Ray number `index` (>= 0).
  virtual PatternRay Ray(std::int64_t index) const = 0;

  /// Rays first .. first + count - 1 into the first `count` columns and entries of `directions_L`
  /// and `lines` (which must be large enough). The default calls Ray() for each.
  virtual void Rays(std::int64_t first, Eigen::Index count, Eigen::Matrix3Xf* directions_L,
                    Eigen::VectorXi* lines) const;
};

/// A procedural model of the Livox MID-360's non-repetitive pattern, fitted to the structure of the
/// official scan table (scan_mode/mid360.csv of Livox-SDK/livox_laser_simulation): four lines fired
/// together in groups (one group per 4 rays); the group's azimuth turns -1.3134 deg per group (one
/// turn in about 5.5 ms at 200,000 points/s); its elevation sweeps from +47.9 deg down to -4.2 deg
/// and back once per 5,000 groups (one 100 ms frame), about linear in the middle and rounded at the
/// ends; the four beams lie on a line through the group's direction, 1.77 and 0.63 deg either side,
/// and that line turns with the azimuth. The leftover 0.24 turn per frame (87 deg) makes successive
/// frames fill each other's gaps. All elevations stay within [-7, +52] deg.
class Mid360Pattern final : public ScanPattern {
 public:
  PatternRay Ray(std::int64_t index) const override;
  /// Computes each group's direction once for its four beams.
  void Rays(std::int64_t first, Eigen::Index count, Eigen::Matrix3Xf* directions_L,
            Eigen::VectorXi* lines) const override;
};

/// A scan table in Livox's format (`scan_mode/mid360.csv` of Livox-SDK/livox_laser_simulation):
/// a header `Time/s,Azimuth/deg,Zenith/deg`, then one row per ray; the first column is a row index,
/// not a time; elevation = 90 deg - zenith; direction (sin z cos a, sin z sin a, cos z). Ray i is
/// row i modulo the number of rows (the table wraps); its line is i modulo 4.
class TablePattern final : public ScanPattern {
 public:
  /// @throws common::InputError naming the file and line for a missing, empty or malformed table.
  static std::unique_ptr<TablePattern> Load(const std::string& path);

  PatternRay Ray(std::int64_t index) const override;

  /// Number of rows.
  std::int64_t size() const { return static_cast<std::int64_t>(directions_L_.size()); }

 private:
  std::vector<Eigen::Vector3f> directions_L_;
};

/// Azimuth [rad] of a direction about +z, in (-pi, pi].
inline float Azimuth(const Eigen::Vector3f& direction) {
  return std::atan2(direction.y(), direction.x());
}

/// Elevation [rad] of a unit direction above the x-y plane.
inline float Elevation(const Eigen::Vector3f& direction) {
  return std::asin(std::max(-1.0f, std::min(1.0f, direction.z())));
}

}  // namespace trav::lidar
