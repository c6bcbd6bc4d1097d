#include "mapping/physical_truth.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "mapping/traversability_mapper.h"

namespace trav::mapping {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
// Spacing of the samples over a wheel's contact patch and under the belly [m]: fine enough that a
// step edge or an obstacle's side on the world's 0.05-0.1 m grid falls between two samples.
constexpr double kWheelSpacing_m = 0.025;
constexpr double kBellySpacing_m = 0.05;

// The wheel signs (x, y) in B, in common::Wheel order: front-left, rear-left, front-right,
// rear-right.
constexpr std::array<std::array<double, 2>, 4> kWheelSigns{
    {{1.0, 1.0}, {-1.0, 1.0}, {1.0, -1.0}, {-1.0, -1.0}}};

// Evenly spaced values from -half to half, at most `spacing` apart, 0 among them (so that a wheel's
// lowest point is a sample), the upper half the exact negation of the lower (so that the body's
// samples are symmetric about B's origin bit for bit: BodySamples::Mirror).
std::vector<double> Span(double half, double spacing) {
  const int intervals = 2 * std::max(1, static_cast<int>(std::ceil(half / spacing)));
  std::vector<double> values(intervals + 1);
  for (int i = 0; i < intervals / 2; ++i) {
    values[i] = -half + 2.0 * half * i / intervals;
    values[intervals - i] = -values[i];
  }
  values[intervals / 2] = 0.0;
  return values;
}

// A sample under the robot, in B, with the rim's height above the wheel's lowest point for wheel
// samples (sqrt(r^2 - a^2), a along the heading).
struct BodySample {
  Eigen::Vector2d p_B;
  double rim_m{0.0};
};

// The samples under the four wheels and under the belly, in B. A wheel's samples run along its
// patch from the back (-r) to the front (+r), `across` of them at each position. The samples are
// symmetric about B's origin: wheel w's sample k mirrors wheel 3 - w's sample n - 1 - k (n a
// wheel's samples), the belly's sample k its sample m - 1 - k (m the belly's).
struct BodySamples {
  std::array<std::vector<BodySample>, 4> wheels;
  std::vector<BodySample> belly;
  std::size_t across{0};
  double reach_m{0.0};  // the farthest sample from B's origin

  explicit BodySamples(const RestingBody& body) {
    const double r = body.wheel_radius_m;
    across = Span(body.wheel_half_width_m, kWheelSpacing_m).size();
    for (std::size_t w = 0; w < 4; ++w) {
      const Eigen::Vector2d centre(kWheelSigns[w][0] * body.wheel_x_m,
                                   kWheelSigns[w][1] * body.wheel_y_m);
      for (const double a : Span(r, kWheelSpacing_m)) {
        for (const double c : Span(body.wheel_half_width_m, kWheelSpacing_m)) {
          wheels[w].push_back(
              {centre + Eigen::Vector2d(a, c), std::sqrt(std::max(0.0, r * r - a * a))});
        }
      }
    }
    for (const double x : Span(body.chassis_half_length_m, kBellySpacing_m)) {
      for (const double y : Span(body.chassis_half_width_m, kBellySpacing_m)) {
        belly.push_back({Eigen::Vector2d(x, y), 0.0});
      }
    }
    for (const auto* part : {&wheels[0], &wheels[1], &wheels[2], &wheels[3], &belly}) {
      for (const BodySample& s : *part) reach_m = std::max(reach_m, s.p_B.norm());
    }
  }
};

// The samples at one heading: each sample's offset from B's origin in W (R_WB p_B), in the order
// of BodySamples, computed once for every cell the heading is assessed at.
struct HeadingSamples {
  std::array<std::vector<Eigen::Vector2d>, 4> wheels_W;
  std::vector<Eigen::Vector2d> belly_W;

  HeadingSamples(const BodySamples& samples, double yaw) {
    const Eigen::Matrix2d R_WB = Eigen::Rotation2Dd(yaw).toRotationMatrix();
    for (std::size_t w = 0; w < 4; ++w) {
      for (const BodySample& s : samples.wheels[w]) wheels_W[w].push_back(R_WB * s.p_B);
    }
    for (const BodySample& s : samples.belly) belly_W.push_back(R_WB * s.p_B);
  }
};

// The surface's height under each sample of a pose, in the order of BodySamples (storage reused
// from pose to pose).
struct SampleHeights {
  std::array<std::vector<double>, 4> wheels;
  std::vector<double> belly;

  explicit SampleHeights(const BodySamples& samples) {
    for (std::size_t w = 0; w < 4; ++w) wheels[w].resize(samples.wheels[w].size());
    belly.resize(samples.belly.size());
  }

  // Looks the heights up on `surface` with the robot at p_W.
  void Gather(const RestingSurface& surface, const Eigen::Vector2d& p_W,
              const HeadingSamples& heading) {
    for (std::size_t w = 0; w < 4; ++w) {
      for (std::size_t k = 0; k < wheels[w].size(); ++k) {
        wheels[w][k] = surface.HeightAt(p_W + heading.wheels_W[w][k]);
      }
    }
    for (std::size_t k = 0; k < belly.size(); ++k) {
      belly[k] = surface.HeightAt(p_W + heading.belly_W[k]);
    }
  }

  // The heights of `heights`' pose turned half a turn about B's origin: each sample takes its
  // mirror's height (BodySamples), the same lookups bit for bit.
  void Mirror(const SampleHeights& heights) {
    for (std::size_t w = 0; w < 4; ++w) {
      std::reverse_copy(heights.wheels[3 - w].begin(), heights.wheels[3 - w].end(),
                        wheels[w].begin());
    }
    std::reverse_copy(heights.belly.begin(), heights.belly.end(), belly.begin());
  }
};

// How the robot rests on the surface whose heights under its samples are `heights`.
PoseAssessment Rest(const SampleHeights& heights, const RestingBody& body,
                    const BodySamples& samples, const GroundTruthConfig& config) {
  PoseAssessment pose;
  // where each wheel's rim first touches the surface
  const std::array<std::vector<double>, 4>& wheel_heights = heights.wheels;
  std::array<double, 4> contact{};
  for (std::size_t w = 0; w < 4; ++w) {
    double axle = -std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < samples.wheels[w].size(); ++k) {
      axle = std::max(axle, wheel_heights[w][k] + samples.wheels[w][k].rim_m);
    }
    contact[w] = axle - body.wheel_radius_m;
  }
  // least-squares plane z = c + gx x + gy y through the four contacts (a rectangle in B)
  const double c = 0.25 * (contact[0] + contact[1] + contact[2] + contact[3]);
  const double gx = (contact[0] + contact[2] - contact[1] - contact[3]) / (4.0 * body.wheel_x_m);
  const double gy = (contact[0] + contact[1] - contact[2] - contact[3]) / (4.0 * body.wheel_y_m);
  auto residual = [&](const Eigen::Vector2d& p_B, double z) {
    return z - (c + gx * p_B.x() + gy * p_B.y());
  };
  // steps up and down along each wheel's patch in the direction of travel, on the profile of the
  // highest point across the wheel at each position (on a slope within the pitch limit the rise
  // over the patch, 2 r tan(slope), stays below the step limits: the pitch governs there)
  for (std::size_t w = 0; w < 4; ++w) {
    double lowest_behind = std::numeric_limits<double>::infinity();
    double highest_behind = -lowest_behind;
    double climb = 0.0, drop = 0.0;
    for (std::size_t i = 0; i < samples.wheels[w].size(); i += samples.across) {
      double profile = -std::numeric_limits<double>::infinity();
      for (std::size_t k = i; k < i + samples.across; ++k) {
        profile = std::max(profile, wheel_heights[w][k]);
      }
      climb = std::max(climb, profile - lowest_behind);
      drop = std::max(drop, highest_behind - profile);
      lowest_behind = std::min(lowest_behind, profile);
      highest_behind = std::max(highest_behind, profile);
    }
    const bool front = kWheelSigns[w][0] > 0.0;
    (front ? pose.front_step_m : pose.step_m) =
        std::max(front ? pose.front_step_m : pose.step_m, climb);
    pose.drop_m = std::max(pose.drop_m, drop);
  }
  pose.belly_m = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < samples.belly.size(); ++k) {
    pose.belly_m = std::max(pose.belly_m, residual(samples.belly[k].p_B, heights.belly[k]));
  }
  pose.pitch_rad = std::atan(gx);
  pose.roll_rad = std::atan(gy);
  // a plane steeper than both limits holds at no heading: the wheels must resist its whole downhill
  // pull whichever way the robot faces (so the diagonal of a too steep slope is not a way up)
  const double tilt_rad = std::atan(std::hypot(gx, gy));
  const double max_tilt_rad = std::max(config.max_pitch_deg, config.max_roll_deg) * kDegToRad;
  const std::array<double, 7> ratios{std::abs(pose.pitch_rad) / (config.max_pitch_deg * kDegToRad),
                                     std::abs(pose.roll_rad) / (config.max_roll_deg * kDegToRad),
                                     tilt_rad / max_tilt_rad,
                                     pose.step_m / config.max_step_m,
                                     pose.front_step_m / config.max_front_step_m,
                                     pose.drop_m / config.max_drop_m,
                                     pose.belly_m / config.clearance_m};
  const auto largest = std::max_element(ratios.begin(), ratios.end());
  const double worst = *largest;
  pose.limit = static_cast<RestingLimit>(largest - ratios.begin());
  pose.cost = std::clamp(worst, 0.0, 1.0);
  pose.traversable = worst < 1.0;
  pose.known = true;
  return pose;
}

}  // namespace

RestingSurface::RestingSurface(const common::GridGeometry& ground_geometry,
                               const Eigen::MatrixXf& ground_m,
                               const common::GridGeometry& obstacle_geometry,
                               const Eigen::MatrixXf& obstacle_top_m)
    : ground_geometry_(ground_geometry),
      ground_m_(ground_m),
      obstacle_geometry_(obstacle_geometry),
      obstacle_top_m_(obstacle_top_m),
      ground_cells_per_m_(1.0 / ground_geometry.resolution_m),
      obstacle_cells_per_m_(1.0 / obstacle_geometry.resolution_m) {}

// The truth looks the surface up some 300 times per pose, 16 poses per cell: common::
// InterpolateBilinear and GridGeometry::CellIndex (a division, std::lround and an optional each)
// took 70 % of the time, so the lookups are written out here with the inverse resolutions.
double RestingSurface::HeightAt(const Eigen::Vector2d& p_W) const {
  const common::GridGeometry& g = ground_geometry_;
  const double fx = std::clamp((p_W.x() - g.origin_W.x()) * ground_cells_per_m_, 0.0,
                               static_cast<double>(g.num_x - 1));
  const double fy = std::clamp((p_W.y() - g.origin_W.y()) * ground_cells_per_m_, 0.0,
                               static_cast<double>(g.num_y - 1));
  const int x0 = std::min(static_cast<int>(fx), g.num_x - 2);
  const int y0 = std::min(static_cast<int>(fy), g.num_y - 2);
  const double tx = fx - x0, ty = fy - y0;
  const double bottom = (1 - tx) * ground_m_(x0, y0) + tx * ground_m_(x0 + 1, y0);
  const double top = (1 - tx) * ground_m_(x0, y0 + 1) + tx * ground_m_(x0 + 1, y0 + 1);
  const double ground = (1 - ty) * bottom + ty * top;
  const common::GridGeometry& o = obstacle_geometry_;
  // the nearest cell centre (p is never far below the origin: callers check Contains)
  const int ix = static_cast<int>((p_W.x() - o.origin_W.x()) * obstacle_cells_per_m_ + 0.5);
  const int iy = static_cast<int>((p_W.y() - o.origin_W.y()) * obstacle_cells_per_m_ + 0.5);
  if (!o.Contains(ix, iy)) return ground;
  // fmax: a NaN top (no obstacle) gives way to the ground
  return std::fmax(ground, obstacle_top_m_(ix, iy));
}

bool RestingSurface::Contains(const Eigen::Vector2d& p_W, double radius_m) const {
  const Eigen::Vector2d low = ground_geometry_.origin_W;
  const Eigen::Vector2d high = ground_geometry_.origin_W + ground_geometry_.Extent();
  return (p_W.array() - radius_m >= low.array()).all() &&
         (p_W.array() + radius_m <= high.array()).all();
}

PoseAssessment AssessPose(const RestingSurface& surface, const Eigen::Vector2d& p_W, double yaw,
                          const RestingBody& body, const GroundTruthConfig& config) {
  const BodySamples samples(body);
  if (!surface.Contains(p_W, samples.reach_m)) return PoseAssessment{};
  SampleHeights heights(samples);
  heights.Gather(surface, p_W, HeadingSamples(samples, yaw));
  return Rest(heights, body, samples, config);
}

std::string HeadingLayer(int k) { return fmt::format("traversability_h{:02d}", k); }

common::GridLayers ComputePhysicalTruth(const common::GridGeometry& map_geometry,
                                        const RestingSurface& surface, const RestingBody& body,
                                        const GroundTruthConfig& config) {
  std::vector<Eigen::Vector2i> cells;
  cells.reserve(static_cast<std::size_t>(map_geometry.num_x) * map_geometry.num_y);
  for (int mx = 0; mx < map_geometry.num_x; ++mx) {
    for (int my = 0; my < map_geometry.num_y; ++my) cells.emplace_back(mx, my);
  }
  return ComputePhysicalTruth(map_geometry, cells, surface, body, config);
}

common::GridLayers ComputePhysicalTruth(const common::GridGeometry& map_geometry,
                                        const std::vector<Eigen::Vector2i>& cells,
                                        const RestingSurface& surface, const RestingBody& body,
                                        const GroundTruthConfig& config) {
  std::vector<std::string> names{layers::kTraversability, layers::kElevation, kTraversableHeadings};
  for (int k = 0; k < config.headings; ++k) names.push_back(HeadingLayer(k));
  common::GridLayers truth(map_geometry, names);
  const BodySamples samples(body);
  Eigen::MatrixXf& best = truth.Layer(layers::kTraversability);
  Eigen::MatrixXf& count = truth.Layer(kTraversableHeadings);
  Eigen::MatrixXf& elevation = truth.Layer(layers::kElevation);
  // with an even number of headings, heading k + headings / 2 is heading k turned half a turn:
  // its samples are heading k's mirrored (BodySamples), so one set of lookups serves both, which
  // halves the truth's time (the lookups are most of it)
  const bool mirrored = config.headings % 2 == 0;
  const int looked_up = mirrored ? config.headings / 2 : config.headings;
  std::vector<Eigen::MatrixXf*> heading_layers;
  for (int k = 0; k < config.headings; ++k) heading_layers.push_back(&truth.Layer(HeadingLayer(k)));
  SampleHeights heights(samples), turned(samples);
  for (int k = 0; k < looked_up; ++k) {
    const HeadingSamples heading(samples, 2.0 * M_PI * k / config.headings);
    Eigen::MatrixXf& layer = *heading_layers[k];
    Eigen::MatrixXf* turned_layer = mirrored ? heading_layers[k + looked_up] : nullptr;
    for (const Eigen::Vector2i& cell : cells) {
      const Eigen::Vector2d p_W = map_geometry.CellCenter(cell.x(), cell.y());
      if (!surface.Contains(p_W, samples.reach_m)) continue;
      heights.Gather(surface, p_W, heading);
      layer(cell.x(), cell.y()) = static_cast<float>(Rest(heights, body, samples, config).cost);
      if (!mirrored) continue;
      turned.Mirror(heights);
      (*turned_layer)(cell.x(), cell.y()) =
          static_cast<float>(Rest(turned, body, samples, config).cost);
    }
  }
  for (const Eigen::Vector2i& cell : cells) {
    const float first = (*heading_layers[0])(cell.x(), cell.y());
    if (std::isnan(first)) continue;
    float lowest = 1.0f;
    int traversable = 0;
    for (const Eigen::MatrixXf* heading_layer : heading_layers) {
      const float cost = (*heading_layer)(cell.x(), cell.y());
      lowest = std::min(lowest, cost);
      if (cost < 1.0f) ++traversable;
    }
    best(cell.x(), cell.y()) = lowest;
    count(cell.x(), cell.y()) = static_cast<float>(traversable);
    elevation(cell.x(), cell.y()) =
        static_cast<float>(surface.HeightAt(map_geometry.CellCenter(cell.x(), cell.y())));
  }
  return truth;
}

}  // namespace trav::mapping
