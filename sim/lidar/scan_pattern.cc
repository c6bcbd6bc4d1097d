#include "sim/lidar/scan_pattern.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>

#include "common/check.h"
#include "common/input_error.h"
#include "common/input_file.h"
#include "sim/lidar/mid360_table.h"

namespace trav::lidar {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// MID-360 structure, as the official scan table shows it.
constexpr int kLines = 4;
constexpr double kAzimuthStepDeg = -1.3134;     // per group
constexpr std::int64_t kGroupsPerSweep = 5000;  // one elevation sweep per 100 ms frame
constexpr double kTopElevationDeg = 47.9;
constexpr double kBottomElevationDeg = -4.2;
constexpr double kStartAzimuthDeg = 269.0;  // the official table starts near 269 deg
constexpr double kBeamOffsetsDeg[kLines] = {-1.77, -0.63, 0.63, 1.77};

// Unit direction of an azimuth and elevation; float trigonometry (the result is float anyway).
Eigen::Vector3f Direction(float azimuth_rad, float elevation_rad) {
  const float c = std::cos(elevation_rad);
  return Eigen::Vector3f(c * std::cos(azimuth_rad), c * std::sin(azimuth_rad),
                         std::sin(elevation_rad));
}

}  // namespace

void ScanPattern::Rays(std::int64_t first, Eigen::Index count, Eigen::Matrix3Xf* directions_L,
                       Eigen::VectorXi* lines) const {
  for (Eigen::Index k = 0; k < count; ++k) {
    const PatternRay ray = Ray(first + k);
    directions_L->col(k) = ray.direction_L;
    (*lines)[k] = ray.line;
  }
}

namespace {

// Direction of a MID-360 group (its four beams share it) and the beams around it.
struct Mid360Group {
  double azimuth_deg;
  double elevation_deg;
  double line_cos;  // the beams' line orientation, turning with the azimuth
  double line_sin;
  double inverse_cos_elevation;

  explicit Mid360Group(std::int64_t group) {
    // azimuth turning steadily, elevation sweeping down and up once per frame
    azimuth_deg = std::fmod(kStartAzimuthDeg + kAzimuthStepDeg * static_cast<double>(group), 360.0);
    const double phase = static_cast<double>(group % kGroupsPerSweep) / kGroupsPerSweep;
    const double s = phase < 0.5 ? 2.0 * phase : 2.0 * (1.0 - phase);  // 0 -> 1 -> 0
    const double sweep = 0.5 * s + 0.25 * (1.0 - std::cos(M_PI * s));  // rounded at both ends
    elevation_deg = kTopElevationDeg + (kBottomElevationDeg - kTopElevationDeg) * sweep;
    line_cos = std::cos(azimuth_deg * kDegToRad);
    line_sin = std::sin(azimuth_deg * kDegToRad);
    inverse_cos_elevation = 1.0 / std::cos(elevation_deg * kDegToRad);
  }

  // the beam of `line` on the line through the group direction
  Eigen::Vector3f Beam(int line) const {
    const double offset_deg = kBeamOffsetsDeg[line];
    const double elevation = (elevation_deg + offset_deg * line_sin) * kDegToRad;
    const double azimuth =
        (azimuth_deg + offset_deg * line_cos * inverse_cos_elevation) * kDegToRad;
    return Direction(static_cast<float>(azimuth), static_cast<float>(elevation));
  }
};

}  // namespace

PatternRay ProceduralMid360Pattern::Ray(std::int64_t index) const {
  PatternRay ray;
  ray.line = static_cast<int>(index % kLines);
  ray.direction_L = Mid360Group(index / kLines).Beam(ray.line);
  return ray;
}

void ProceduralMid360Pattern::Rays(std::int64_t first, Eigen::Index count,
                                   Eigen::Matrix3Xf* directions_L, Eigen::VectorXi* lines) const {
  Eigen::Index k = 0;
  while (k < count) {
    const std::int64_t index = first + k;
    const Mid360Group group(index / kLines);
    for (int line = static_cast<int>(index % kLines); line < kLines && k < count; ++line, ++k) {
      directions_L->col(k) = group.Beam(line);
      (*lines)[k] = line;
    }
  }
}

std::unique_ptr<TablePattern> TablePattern::Load(const std::string& path) {
  return Parse(common::ReadInputFile(path, "scan table"), path);
}

std::unique_ptr<TablePattern> TablePattern::Parse(std::string_view text, const std::string& name) {
  std::istringstream file{std::string(text)};
  auto table = std::make_unique<TablePattern>();
  std::string line;
  int line_number = 0;
  while (std::getline(file, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line_number == 1) {
      if (line.rfind("Time/s,Azimuth/deg,Zenith/deg", 0) != 0) {
        throw common::InputError(
            name, "line 1",
            "expected the header 'Time/s,Azimuth/deg,Zenith/deg' (is this a scan table?)");
      }
      continue;
    }
    std::stringstream row(line);
    double values[3];
    char comma = ',';
    bool ok = static_cast<bool>(row >> values[0]);
    for (int k = 1; k < 3 && ok; ++k)
      ok = static_cast<bool>(row >> comma >> values[k]) && comma == ',';
    std::string rest;
    if (!ok || (row >> rest) || !std::isfinite(values[1]) || !std::isfinite(values[2]) ||
        values[2] < 0.0 || values[2] > 180.0) {
      throw common::InputError(
          name, "line " + std::to_string(line_number),
          "expected 'index,azimuth_deg,zenith_deg' with zenith in [0, 180], got " +
              common::QuotedExcerpt(line));
    }
    const double azimuth = values[1] * kDegToRad;
    const double zenith = values[2] * kDegToRad;
    table->directions_L_.push_back(Eigen::Vector3d(std::sin(zenith) * std::cos(azimuth),
                                                   std::sin(zenith) * std::sin(azimuth),
                                                   std::cos(zenith))
                                       .cast<float>());
  }
  if (table->directions_L_.empty())
    throw common::InputError(name, "", "the scan table has no rows");
  table->period_ = table->size();
  return table;
}

std::shared_ptr<const TablePattern> TablePattern::Mid360() {
  static const std::shared_ptr<const TablePattern> shipped = [] {
    std::shared_ptr<TablePattern> table =
        Parse(Mid360TableText(), "sim/lidar/data/livox_mid360/mid360_scan_head.csv");
    constexpr std::int64_t kPassRows = 40000;  // two frames: one elevation sweep each
    TRAV_DEMAND(table->size() > kPassRows);
    table->period_ = kPassRows;
    table->turn_per_pass_rad_ =
        std::remainder(static_cast<double>(Azimuth(table->directions_L_[kPassRows])) -
                           static_cast<double>(Azimuth(table->directions_L_[0])),
                       2.0 * M_PI);
    return table;
  }();
  return shipped;
}

Eigen::Matrix2f TablePattern::PassTurn(std::int64_t pass) const {
  const double angle = std::remainder(turn_per_pass_rad_ * static_cast<double>(pass), 2.0 * M_PI);
  return Eigen::Rotation2Df(static_cast<float>(angle)).toRotationMatrix();
}

PatternRay TablePattern::Ray(std::int64_t index) const {
  PatternRay ray;
  const std::int64_t row = index % period_;
  ray.direction_L = directions_L_[static_cast<std::size_t>(row)];
  ray.direction_L.head<2>() = PassTurn(index / period_) * ray.direction_L.head<2>();
  ray.line = static_cast<int>(row % kLines);
  return ray;
}

void TablePattern::Rays(std::int64_t first, Eigen::Index count, Eigen::Matrix3Xf* directions_L,
                        Eigen::VectorXi* lines) const {
  Eigen::Index k = 0;
  while (k < count) {
    const std::int64_t index = first + k;
    const Eigen::Matrix2f turn = PassTurn(index / period_);
    for (std::int64_t row = index % period_; row < period_ && k < count; ++row, ++k) {
      const Eigen::Vector3f& direction = directions_L_[static_cast<std::size_t>(row)];
      directions_L->col(k) << turn * direction.head<2>(), direction.z();
      (*lines)[k] = static_cast<int>(row % kLines);
    }
  }
}

}  // namespace trav::lidar
