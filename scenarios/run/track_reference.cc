#include "scenarios/run/track_reference.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "common/input_error.h"
#include "common/input_file.h"

namespace trav::scenarios {
namespace {

// Curve points every centimetre or closer, in the reference's own frame (start at the origin,
// heading +x).
std::vector<Eigen::Vector2d> ShapePoints(const TrackSettings& s) {
  std::vector<Eigen::Vector2d> points;
  switch (s.reference) {
    case ReferenceShape::kLine:
      for (double x = 0.0; x <= s.size_m + 1e-9; x += 0.01) points.emplace_back(x, 0.0);
      break;
    case ReferenceShape::kCircle:
      // counter-clockwise, centre on the left
      for (double a = 0.0; a <= 2.0 * M_PI + 1e-9; a += 0.01 / s.size_m) {
        points.emplace_back(s.size_m * std::sin(a), s.size_m * (1.0 - std::cos(a)));
      }
      break;
    case ReferenceShape::kFigureEight:
      // lemniscate of Gerono: two lobes through the start
      for (double a = 0.0; a <= 2.0 * M_PI + 1e-9; a += 0.002) {
        points.emplace_back(s.size_m * std::sin(a), s.size_m * std::sin(a) * std::cos(a));
      }
      break;
    case ReferenceShape::kSlalom:
      for (double x = 0.0; x <= s.size_m + 1e-9; x += 0.01) {
        points.emplace_back(x, s.amplitude_m * std::sin(2.0 * M_PI * x / s.wavelength_m));
      }
      break;
    case ReferenceShape::kFile:
      break;
  }
  return points;
}

common::Trajectory LoadReference(const std::string& path) {
  std::istringstream file(common::ReadInputFile(path, "reference trajectory"));
  std::string line;
  std::getline(file, line);
  if (line.rfind("t,x,y,yaw,v,omega", 0) != 0) {
    throw common::InputError(path, "line 1",
                             "expected the header 't,x,y,yaw,v,omega' (is this a trajectory?)");
  }
  std::vector<common::TrajectoryPoint> points;
  for (int number = 2; std::getline(file, line); ++number) {
    if (line.empty()) continue;
    std::stringstream row(line);
    double values[6];
    bool ok = true;
    for (int k = 0; k < 6 && ok; ++k) {
      char comma = ',';
      ok = static_cast<bool>(row >> values[k]) && (k == 5 || (row >> comma && comma == ','));
    }
    if (!ok || !std::all_of(values, values + 6, [](double v) { return std::isfinite(v); }) ||
        (!points.empty() && values[0] <= points.back().t_s)) {
      throw common::InputError(
          path, "line " + std::to_string(number),
          "expected 6 finite numbers with increasing t, got " + common::QuotedExcerpt(line));
    }
    common::TrajectoryPoint p;
    p.t_s = values[0];
    p.position_W = Eigen::Vector2d(values[1], values[2]);
    p.yaw = values[3];
    p.v = values[4];
    p.omega = values[5];
    points.push_back(p);
  }
  if (points.size() < 2) throw common::InputError(path, "track.file", "needs at least 2 points");
  return common::Trajectory(std::move(points));
}

}  // namespace

common::Trajectory BuildReference(const TrackSettings& settings, const common::Pose2& start_W) {
  if (settings.reference == ReferenceShape::kFile) return LoadReference(settings.file);
  // place the shape at the start pose, its initial tangent along the start heading
  std::vector<Eigen::Vector2d> path = ShapePoints(settings);
  const Eigen::Vector2d tangent = path[std::min<std::size_t>(5, path.size() - 1)] - path.front();
  const Eigen::Rotation2Dd R_WS(start_W.yaw - std::atan2(tangent.y(), tangent.x()));
  for (Eigen::Vector2d& p : path) p = start_W.position + R_WS * p;
  return common::TrajectoryAlongPath(path, settings.speed_m_s, settings.acceleration_m_s2);
}

}  // namespace trav::scenarios
