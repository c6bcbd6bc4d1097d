#include "mapping/mover_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace trav::mapping {
namespace {

using Cell = std::pair<int, int>;

Cell CellOf(const Eigen::Vector2d& p, double size) {
  return {static_cast<int>(std::floor(p.x() / size)), static_cast<int>(std::floor(p.y() / size))};
}

// A cluster of object points: centroid and footprint radius.
struct Cluster {
  Eigen::Vector2d centroid_W{Eigen::Vector2d::Zero()};
  double radius_m{0.0};
};

// An object point: its position and its height above its column's lowest point [m].
struct ObjectPoint {
  Eigen::Vector2d xy_W;
  double above_m;
};

// Object points: above their column's lowest point by the minimum height, within the range.
std::vector<ObjectPoint> ObjectPoints(const common::PointCloud& cloud, const Eigen::Vector3d& p_WB,
                                      const MoverTrackerConfig& c) {
  std::map<Cell, float> ground;
  for (Eigen::Index i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f p = cloud.points.col(i);
    if (!p.allFinite()) continue;
    const Cell cell = CellOf(p.head<2>().cast<double>(), c.column_m);
    const auto it = ground.find(cell);
    if (it == ground.end() || p.z() < it->second) ground[cell] = p.z();
  }
  std::vector<ObjectPoint> objects;
  for (Eigen::Index i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f p = cloud.points.col(i);
    if (!p.allFinite()) continue;
    const Eigen::Vector2d xy = p.head<2>().cast<double>();
    if ((xy - p_WB.head<2>()).norm() > c.range_m) continue;
    const double above = p.z() - ground.at(CellOf(xy, c.column_m));
    if (above >= c.min_height_m && above <= c.max_height_m) objects.push_back({xy, above});
  }
  return objects;
}

// 8-connected components of the occupied grid cells; clusters no larger than the maximum radius.
std::vector<Cluster> Clusters(const std::vector<ObjectPoint>& points, const MoverTrackerConfig& c) {
  std::map<Cell, std::vector<ObjectPoint>> cells;
  for (const ObjectPoint& p : points) cells[CellOf(p.xy_W, c.cell_m)].push_back(p);
  std::map<Cell, bool> visited;
  std::vector<Cluster> clusters;
  for (const auto& [seed, unused] : cells) {
    if (visited[seed]) continue;
    std::vector<Cell> stack = {seed};
    visited[seed] = true;
    std::vector<ObjectPoint> members;
    while (!stack.empty()) {
      const Cell cell = stack.back();
      stack.pop_back();
      const std::vector<ObjectPoint>& in_cell = cells.at(cell);
      members.insert(members.end(), in_cell.begin(), in_cell.end());
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          const Cell next{cell.first + dx, cell.second + dy};
          if (cells.count(next) == 0 || visited[next]) continue;
          visited[next] = true;
          stack.push_back(next);
        }
      }
    }
    Cluster cluster;
    double top_m = 0.0;
    for (const ObjectPoint& p : members) {
      cluster.centroid_W += p.xy_W;
      top_m = std::max(top_m, p.above_m);
    }
    cluster.centroid_W /= static_cast<double>(members.size());
    for (const ObjectPoint& p : members) {
      cluster.radius_m = std::max(cluster.radius_m, (p.xy_W - cluster.centroid_W).norm());
    }
    if (static_cast<int>(members.size()) >= c.min_points && cluster.radius_m <= c.max_radius_m &&
        top_m >= c.min_top_m) {
      clusters.push_back(cluster);
    }
  }
  return clusters;
}

}  // namespace

MoverTracker::MoverTracker(const MoverTrackerConfig& config) : config_(config) {}

void MoverTracker::Update(const common::PointCloud& points_W, const Eigen::Vector3d& p_WB,
                          double t_s) {
  const std::vector<Cluster> clusters = Clusters(ObjectPoints(points_W, p_WB, config_), config_);
  // greedy nearest matching of clusters to predicted tracks, closest pairs first
  std::vector<std::pair<double, std::pair<std::size_t, std::size_t>>> pairs;
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    const TrackedMover& track = tracks_[k];
    const Eigen::Vector2d predicted = track.position_W + (t_s - track.t_s) * track.velocity_W;
    for (std::size_t j = 0; j < clusters.size(); ++j) {
      const double d = (clusters[j].centroid_W - predicted).norm();
      if (d <= config_.gate_m) pairs.push_back({d, {k, j}});
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> track_used(tracks_.size(), false), cluster_used(clusters.size(), false);
  for (const auto& [distance, match] : pairs) {
    const auto [k, j] = match;
    if (track_used[k] || cluster_used[j]) continue;
    track_used[k] = cluster_used[j] = true;
    TrackedMover& track = tracks_[k];
    const double dt = t_s - track.t_s;
    if (dt <= 0.0) continue;
    const Eigen::Vector2d predicted = track.position_W + dt * track.velocity_W;
    const Eigen::Vector2d residual = clusters[j].centroid_W - predicted;
    track.position_W = predicted + config_.alpha * residual;
    // the first update measures the velocity outright; later ones filter it
    track.velocity_W = track.updates == 1
                           ? Eigen::Vector2d(residual / dt + track.velocity_W)
                           : Eigen::Vector2d(track.velocity_W + config_.beta / dt * residual);
    track.radius_m = clusters[j].radius_m;
    track.t_s = t_s;
    ++track.updates;
    // keep one position at or before the window's start: the displacement is measured from it
    track.recent_W.emplace_back(t_s, track.position_W);
    while (track.recent_W.size() > 2 &&
           track.recent_W[1].first <= t_s - config_.displacement_window_s) {
      track.recent_W.pop_front();
    }
    const auto& [then_s, then_W] = track.recent_W.front();
    if (track.updates >= config_.min_updates && then_s <= t_s - config_.displacement_window_s &&
        track.velocity_W.norm() >= config_.min_speed_m_s &&
        (track.position_W - then_W).norm() >= config_.min_displacement_m) {
      track.last_moving_t_s = t_s;
    }
  }
  for (std::size_t j = 0; j < clusters.size(); ++j) {
    if (cluster_used[j]) continue;
    TrackedMover track;
    track.id = next_id_++;
    track.position_W = clusters[j].centroid_W;
    track.recent_W.emplace_back(t_s, track.position_W);
    track.radius_m = clusters[j].radius_m;
    track.t_s = t_s;
    track.updates = 1;
    tracks_.push_back(track);
  }
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const TrackedMover& track) {
                                 return t_s - track.t_s > config_.drop_after_s;
                               }),
                tracks_.end());
}

std::vector<TrackedMover> MoverTracker::Movers() const {
  std::vector<TrackedMover> movers;
  for (const TrackedMover& track : tracks_) {
    if (track.t_s - track.last_moving_t_s <= config_.hold_s) movers.push_back(track);
  }
  return movers;
}

}  // namespace trav::mapping
