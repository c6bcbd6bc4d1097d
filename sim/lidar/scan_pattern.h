#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
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
class ProceduralMid360Pattern final : public ScanPattern {
 public:
  PatternRay Ray(std::int64_t index) const override;
  /// Computes each group's direction once for its four beams.
  void Rays(std::int64_t first, Eigen::Index count, Eigen::Matrix3Xf* directions_L,
            Eigen::VectorXi* lines) const override;
};

/// A scan table in Livox's format (`scan_mode/mid360.csv` of Livox-SDK/livox_laser_simulation):
/// a header `Time/s,Azimuth/deg,Zenith/deg`, then one row per ray; the first column is a row index,
/// not a time; elevation = 90 deg - zenith; direction (sin z cos a, sin z sin a, cos z).
///
/// The rays go through the first period() rows again and again (a pass); pass p is turned about +z
/// by p * azimuth_turn_per_pass_rad(). A loaded table has period() = size() and no turn (it wraps,
/// as Livox's simulator does); the shipped MID-360 table (Mid360()) turns so that its frames never
/// repeat. Ray i is row r = i modulo period(); its line is r modulo 4.
class TablePattern final : public ScanPattern {
 public:
  /// @throws common::InputError naming the file and line for a missing, empty or malformed table.
  static std::unique_ptr<TablePattern> Load(const std::string& path);

  /// A table from its text; `name` stands for the file in error messages.
  /// @throws common::InputError naming `name` and the line for an empty or malformed table.
  static std::unique_ptr<TablePattern> Parse(std::string_view text, const std::string& name);

  /// The default pattern: the head of Livox's MID-360 table shipped in the tree
  /// (sim/lidar/data/livox_mid360, two 100 ms frames and a half at 200,000 points/s), parsed once
  /// per process. Its passes are the first 40,000 rows (rows 0 and 40,000 both begin an elevation
  /// sweep), each turned on by the azimuth that the table itself advances from row 0 to row 40,000
  /// (-173.7 deg), so the sequence continues where the table goes on and successive passes fill
  /// each other's gaps as the real sensor's frames do.
  static std::shared_ptr<const TablePattern> Mid360();

  PatternRay Ray(std::int64_t index) const override;
  /// Turns each pass once for all its rays.
  void Rays(std::int64_t first, Eigen::Index count, Eigen::Matrix3Xf* directions_L,
            Eigen::VectorXi* lines) const override;

  /// Number of rows.
  std::int64_t size() const { return static_cast<std::int64_t>(directions_L_.size()); }
  /// Rows per pass, in [1, size()].
  std::int64_t period() const { return period_; }
  /// Turn about +z from one pass to the next [rad].
  double azimuth_turn_per_pass_rad() const { return turn_per_pass_rad_; }

 private:
  // The turn of pass `pass` in the x-y plane.
  Eigen::Matrix2f PassTurn(std::int64_t pass) const;

  std::vector<Eigen::Vector3f> directions_L_;
  std::int64_t period_{0};
  double turn_per_pass_rad_{0.0};
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
