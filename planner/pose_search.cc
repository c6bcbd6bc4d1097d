#include "planner/pose_search.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <tuple>

namespace trav::planner {
namespace {

constexpr int kHeadings = 16;

// The step of each heading [cells], counter-clockwise from +x: the 5 x 5 neighbourhood's outer
// cells that no nearer cell lies in front of.
constexpr std::array<std::array<int, 2>, kHeadings> kSteps{{{1, 0},
                                                            {2, 1},
                                                            {1, 1},
                                                            {1, 2},
                                                            {0, 1},
                                                            {-1, 2},
                                                            {-1, 1},
                                                            {-2, 1},
                                                            {-1, 0},
                                                            {-2, -1},
                                                            {-1, -1},
                                                            {-1, -2},
                                                            {0, -1},
                                                            {1, -2},
                                                            {1, -1},
                                                            {2, -1}}};

// Turns merged into one pose stay within this [rad], so that the shorter way round is theirs.
constexpr double kMaxMergedTurn_rad = 0.75 * M_PI;

// How a state was reached: from the start (a turn in place to its heading), or from its parent.
enum class Move : std::uint8_t { kStart, kTurn, kForward, kReverse };

double HeadingYaw(int k) { return std::atan2(kSteps[k][1], kSteps[k][0]); }

// The lattice of poses round the start and its A*: states are offsets (i, j) in [-reach, reach]
// cells from the start, and a heading; a state within one cell of the goal reaches it.
class PoseLattice {
 public:
  PoseLattice(const CostField& field, const std::vector<Eigen::Vector2d>& body_points_B,
              double circumscribed_radius_m, double clearance_m, const common::Pose2& start,
              const Eigen::Vector2d& goal_W, const FallbackConfig& config)
      : field_(field),
        body_points_B_(body_points_B),
        circumscribed_radius_m_(circumscribed_radius_m),
        start_(start),
        goal_W_(goal_W),
        config_(config),
        resolution_m_(field.geometry().resolution_m),
        floor_m_(std::min(clearance_m,
                          FootprintDistance(field, start.position, start.yaw, body_points_B)) -
                 1e-9),
        reach_(static_cast<int>(std::ceil(config.search_reach_m / resolution_m_)) + 1),
        side_(2 * reach_ + 1),
        count_(static_cast<std::size_t>(side_) * side_ * kHeadings),
        cost_s_(count_, std::numeric_limits<double>::infinity()),
        parent_(count_, count_),
        move_(count_, Move::kStart),
        closed_(count_, false) {}

  // A* to the first state within the tolerance of the goal, if any within the expansions.
  std::optional<std::size_t> Search() {
    for (int k = 0; k < kHeadings; ++k) {
      const double turn = std::remainder(HeadingYaw(k) - start_.yaw, 2.0 * M_PI);
      if (TurnClear(start_.position, start_.yaw, turn)) {
        Relax(Index(0, 0, k), count_, Move::kStart, std::abs(turn) / config_.creep_yaw_rate_rad_s);
      }
    }
    int expansions = 0;
    while (!open_.empty() && expansions < config_.search_expansions) {
      const std::size_t s = std::get<2>(open_.top());
      open_.pop();
      if (closed_[s]) continue;
      closed_[s] = true;
      ++expansions;
      if ((Position(s) - goal_W_).norm() <= resolution_m_) return s;
      Expand(s);
    }
    return std::nullopt;
  }

  // The way to `reached` as SearchPoses returns it: one pose per turn-then-drive; turns in one
  // sense merge while they stay short of kMaxMergedTurn, drives in one sense merge, a drive merges
  // into the turn before it.
  std::vector<common::Pose2> Poses(std::size_t reached) const {
    std::vector<std::size_t> chain;
    for (std::size_t s = reached; s != count_; s = parent_[s]) chain.push_back(s);
    std::reverse(chain.begin(), chain.end());
    std::vector<common::Pose2> poses;
    int drive = 0;      // the last pose's drive: +1 forward, -1 backward, 0 none (a turn only)
    double turned = 0;  // the last pose's turn [rad]
    double yaw = start_.yaw;
    for (const std::size_t s : chain) {
      common::Pose2 pose;
      pose.position = Position(s);
      pose.yaw = HeadingYaw(static_cast<int>(s % kHeadings));
      if (move_[s] == Move::kStart || move_[s] == Move::kTurn) {
        const double turn = std::remainder(pose.yaw - yaw, 2.0 * M_PI);
        if (!poses.empty() && drive == 0 && turn * turned > 0.0 &&
            std::abs(turned + turn) <= kMaxMergedTurn_rad) {
          poses.back().yaw = pose.yaw;
          turned += turn;
        } else {
          poses.push_back(pose);
          drive = 0;
          turned = turn;
        }
      } else {
        const int direction = move_[s] == Move::kForward ? 1 : -1;
        if (!poses.empty() && (drive == 0 || drive == direction)) {
          poses.back().position = pose.position;
        } else {
          poses.push_back(pose);
          turned = 0.0;
        }
        drive = direction;
      }
      yaw = pose.yaw;
    }
    return poses;
  }

 private:
  using Entry = std::tuple<double, std::uint64_t, std::size_t>;  // (f, order found, state)

  std::size_t Index(int i, int j, int k) const {
    return (static_cast<std::size_t>(i + reach_) * side_ + static_cast<std::size_t>(j + reach_)) *
               kHeadings +
           static_cast<std::size_t>(k);
  }

  Eigen::Vector2d Position(std::size_t s) const {
    const int cell = static_cast<int>(s / kHeadings);
    return start_.position +
           resolution_m_ * Eigen::Vector2d(cell / side_ - reach_, cell % side_ - reach_);
  }

  bool ClearAt(const Eigen::Vector2d& p_W, double yaw) const {
    return FootprintDistance(field_, p_W, yaw, body_points_B_) >= floor_m_;
  }

  // Samples so that no body point moves more than half a cell between them, the end included.
  int Samples(double motion_m) const {
    return std::max(1, static_cast<int>(std::ceil(motion_m / (0.5 * resolution_m_))));
  }

  bool DriveClear(const Eigen::Vector2d& from_W, const Eigen::Vector2d& to_W, double yaw) const {
    const int n = Samples((to_W - from_W).norm());
    for (int s = 1; s <= n; ++s) {
      if (!ClearAt(from_W + (to_W - from_W) * (static_cast<double>(s) / n), yaw)) return false;
    }
    return true;
  }

  bool TurnClear(const Eigen::Vector2d& p_W, double from_yaw, double turn_rad) const {
    const int n = Samples(std::abs(turn_rad) * circumscribed_radius_m_);
    for (int s = 1; s <= n; ++s) {
      if (!ClearAt(p_W, from_yaw + turn_rad * (static_cast<double>(s) / n))) return false;
    }
    return true;
  }

  void Relax(std::size_t s, std::size_t from, Move how, double cost_s) {
    if (cost_s >= cost_s_[s]) return;
    cost_s_[s] = cost_s;
    parent_[s] = from;
    move_[s] = how;
    const double heuristic_s =
        std::max(0.0, (Position(s) - goal_W_).norm() - resolution_m_) / config_.creep_speed_m_s;
    open_.emplace(cost_s + heuristic_s, order_++, s);
  }

  // Relaxes the turns to the neighbouring headings and the drives one step forward and back.
  void Expand(std::size_t s) {
    const Eigen::Vector2d p_W = Position(s);
    const int cell = static_cast<int>(s / kHeadings);
    const int i = cell / side_ - reach_, j = cell % side_ - reach_;
    const int k = static_cast<int>(s % kHeadings);
    const double yaw = HeadingYaw(k);
    for (const int step : {1, kHeadings - 1}) {
      const int to = (k + step) % kHeadings;
      const double turn = std::remainder(HeadingYaw(to) - yaw, 2.0 * M_PI);
      const std::size_t next = Index(i, j, to);
      if (!closed_[next] && TurnClear(p_W, yaw, turn)) {
        Relax(next, s, Move::kTurn, cost_s_[s] + std::abs(turn) / config_.creep_yaw_rate_rad_s);
      }
    }
    for (const int direction : {1, -1}) {
      const int ni = i + direction * kSteps[k][0], nj = j + direction * kSteps[k][1];
      if (std::abs(ni) > reach_ || std::abs(nj) > reach_) continue;
      const std::size_t next = Index(ni, nj, k);
      const Eigen::Vector2d to_W = Position(next);
      if (closed_[next] || !DriveClear(p_W, to_W, yaw)) continue;
      const double time_s = (to_W - p_W).norm() / config_.creep_speed_m_s;
      Relax(next, s, direction > 0 ? Move::kForward : Move::kReverse,
            cost_s_[s] + (direction > 0 ? time_s : kPoseSearchReverseFactor * time_s));
    }
  }

  const CostField& field_;
  const std::vector<Eigen::Vector2d>& body_points_B_;
  double circumscribed_radius_m_;
  common::Pose2 start_;
  Eigen::Vector2d goal_W_;
  FallbackConfig config_;
  double resolution_m_;
  double floor_m_;  // the smallest footprint distance admitted [m]
  int reach_;       // [cells]
  int side_;        // 2 reach + 1
  std::size_t count_;
  std::vector<double> cost_s_;
  std::vector<std::size_t> parent_;  // count_: none (the start)
  std::vector<Move> move_;
  std::vector<bool> closed_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open_;
  std::uint64_t order_{0};
};

}  // namespace

std::optional<std::vector<common::Pose2>> SearchPoses(
    const CostField& field, const std::vector<Eigen::Vector2d>& body_points_B,
    double circumscribed_radius_m, double clearance_m, const common::Pose2& start,
    const Eigen::Vector2d& goal_W, const FallbackConfig& config) {
  if ((start.position - goal_W).norm() <= field.geometry().resolution_m) {
    return std::vector<common::Pose2>{};
  }
  PoseLattice lattice(field, body_points_B, circumscribed_radius_m, clearance_m, start, goal_W,
                      config);
  const std::optional<std::size_t> reached = lattice.Search();
  if (!reached) return std::nullopt;
  return lattice.Poses(*reached);
}

}  // namespace trav::planner
