#include "mapping/physical_truth.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "mapping/traversability_mapper.h"
#include "tests/mapping/sampled_grid.h"

namespace trav::mapping {
namespace {

constexpr double kDeg = M_PI / 180.0;
const common::GridGeometry kWorld =
    common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(6, 6), 0.1);
const common::GridGeometry kMap =
    common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(6, 6), 0.2);

Eigen::MatrixXf Sampled(const std::function<double(double, double)>& height) {
  return test_util::Sampled(kWorld, height);
}

const Eigen::MatrixXf kFlat = Sampled([](double, double) { return 0.0; });
// Obstacle tops: none anywhere.
const Eigen::MatrixXf kNoObstacles = Sampled([](double, double) { return std::nan(""); });

// A plane rising along +x at `angle_deg`.
Eigen::MatrixXf Slope(double angle_deg) {
  return Sampled([angle_deg](double x, double) { return std::tan(angle_deg * kDeg) * x; });
}

common::GridLayers Truth(const Eigen::MatrixXf& ground, const Eigen::MatrixXf& obstacles) {
  return ComputePhysicalTruth(kMap, RestingSurface{kWorld, ground, kWorld, obstacles},
                              RestingBody{}, GroundTruthConfig{});
}

PoseAssessment At(const Eigen::MatrixXf& ground, const Eigen::MatrixXf& obstacles, double x,
                  double yaw_deg) {
  const RestingSurface surface{kWorld, ground, kWorld, obstacles};
  return AssessPose(surface, Eigen::Vector2d(x, 0.0), yaw_deg * kDeg, RestingBody{},
                    GroundTruthConfig{});
}

TEST(PhysicalTruthTest, FlatGroundIsFreeAtEveryHeadingAndTheRimIsUnknown) {
  const common::GridLayers truth = Truth(kFlat, kNoObstacles);
  const Eigen::MatrixXf& cost = truth.Layer(layers::kTraversability);
  EXPECT_EQ(cost(15, 15), 0.0f);
  EXPECT_EQ(truth.Layer(kTraversableHeadings)(15, 15), 16.0f);
  EXPECT_EQ(truth.Layer(HeadingLayer(5))(15, 15), 0.0f);
  // a robot centred on the border cell would stand half off the world; so would one 0.4 m in
  // turned across the corner (its wheels' outer corners are 0.42 m from its centre)
  EXPECT_TRUE(std::isnan(cost(0, 15)));
  EXPECT_TRUE(std::isnan(cost(2, 15)));
  EXPECT_FALSE(std::isnan(cost(3, 15)));
}

TEST(PhysicalTruthTest, AFifteenDegreeSlopeIsTraversableAlongAndAcross) {
  const Eigen::MatrixXf ground = Slope(15.0);
  const PoseAssessment up = At(ground, kNoObstacles, 0.0, 0.0);
  EXPECT_NEAR(up.pitch_rad, 15.0 * kDeg, 1e-4);
  EXPECT_NEAR(up.roll_rad, 0.0, 1e-6);
  EXPECT_NEAR(up.cost, 15.0 / 40.0, 1e-3);
  // the rise over a wheel's patch (2 r tan 15 deg) is no step the robot cannot take
  EXPECT_NEAR(up.step_m, 2.0 * 0.0875 * std::tan(15.0 * kDeg), 1e-5);
  EXPECT_TRUE(up.traversable);
  const PoseAssessment across = At(ground, kNoObstacles, 0.0, 90.0);
  EXPECT_NEAR(std::abs(across.roll_rad), 15.0 * kDeg, 1e-4);
  EXPECT_NEAR(across.pitch_rad, 0.0, 1e-6);
  EXPECT_TRUE(across.traversable);
  const common::GridLayers truth = Truth(ground, kNoObstacles);
  EXPECT_EQ(truth.Layer(kTraversableHeadings)(15, 15), 16.0f);
  EXPECT_NEAR(truth.Layer(layers::kTraversability)(15, 15), 15.0 / 40.0, 1e-3);
}

TEST(PhysicalTruthTest, ASlopePastTheLimitIsUntraversableAtEveryHeading) {
  const common::GridLayers truth = Truth(Slope(42.0), kNoObstacles);
  EXPECT_EQ(truth.Layer(layers::kTraversability)(15, 15), 1.0f);
  EXPECT_EQ(truth.Layer(kTraversableHeadings)(15, 15), 0.0f);
  // 38 deg is within both limits
  const common::GridLayers steep = Truth(Slope(38.0), kNoObstacles);
  EXPECT_EQ(steep.Layer(kTraversableHeadings)(15, 15), 16.0f);
}

// A step at x = 0, `height_m` higher for x > 0 (the height field's ramp from x = 0 to 0.1 m, as
// MuJoCo's).
Eigen::MatrixXf Step(double height_m) {
  return Sampled([height_m](double x, double) { return x > 0.0 ? height_m : 0.0; });
}

// The poses of a drive across the step, up it (+x) or down it (-x), every 0.01 m over 1.2 m
// centred on the edge.
std::vector<PoseAssessment> DriveOverStep(double height_m, bool up) {
  const Eigen::MatrixXf ground = Step(height_m);
  std::vector<PoseAssessment> poses;
  for (int i = 0; i <= 120; ++i) {
    const double x = (up ? -0.6 : 0.6) + (up ? 0.01 : -0.01) * i;
    poses.push_back(At(ground, kNoObstacles, x, up ? 0.0 : 180.0));
  }
  return poses;
}

bool Crosses(const std::vector<PoseAssessment>& poses) {
  return std::all_of(poses.begin(), poses.end(),
                     [](const PoseAssessment& pose) { return pose.traversable; });
}

TEST(PhysicalTruthTest, StepsUpAndDownAgainstTheMeasuredLimits) {
  // up: the robot climbs 0.16 m (its rear wheels), not 0.17 m
  EXPECT_TRUE(Crosses(DriveOverStep(0.10, true)));
  EXPECT_TRUE(Crosses(DriveOverStep(0.15, true)));
  EXPECT_FALSE(Crosses(DriveOverStep(0.17, true)));
  EXPECT_FALSE(Crosses(DriveOverStep(0.30, true)));
  // down: a drop of 0.27 m tilts it 45 deg; resting across the edge of a 0.2 m drop its belly
  // touches the corner (quasi-static: at speed the front wheels fly clear)
  EXPECT_TRUE(Crosses(DriveOverStep(0.10, false)));
  EXPECT_FALSE(Crosses(DriveOverStep(0.20, false)));
  EXPECT_FALSE(Crosses(DriveOverStep(0.30, false)));
  double deepest = 0.0;
  for (const PoseAssessment& pose : DriveOverStep(0.30, false)) {
    deepest = std::max(deepest, pose.drop_m);
    EXPECT_EQ(pose.step_m + pose.front_step_m, 0.0);
  }
  EXPECT_NEAR(deepest, 0.30, 1e-6);
  // up 0.2 m: the front wheels get onto it (0.2 of 0.22 m), the rear wheels do not (0.16 m)
  double front = 0.0, rear = 0.0, drop = 0.0;
  bool front_on_edge_is_traversable = false;
  for (const PoseAssessment& pose : DriveOverStep(0.20, true)) {
    front = std::max(front, pose.front_step_m);
    rear = std::max(rear, pose.step_m);
    drop = std::max(drop, pose.drop_m);
    if (pose.front_step_m > 0.15 && pose.step_m == 0.0) {
      front_on_edge_is_traversable = pose.traversable;
    }
  }
  EXPECT_GT(front, 0.18);
  EXPECT_LE(front, 0.2 + 1e-6);
  EXPECT_GT(rear, 0.18);
  EXPECT_LT(drop, 0.02);
  EXPECT_TRUE(front_on_edge_is_traversable);
  // parallel to the edge, on it, the robot stands with one side up: 0.2 m over the track is within
  // the roll limit, and no wheel climbs
  const PoseAssessment along = At(Step(0.2), kNoObstacles, 0.0, 90.0);
  EXPECT_NEAR(std::abs(along.roll_rad), std::atan(0.2 / 0.49), 0.03);
  EXPECT_LT(along.step_m + along.front_step_m, 1e-9);
}

TEST(PhysicalTruthTest, ABoxTallerThanTheBellyClearanceBetweenTheWheelsIsNotTraversable) {
  auto box = [](double height_m) {
    return Sampled([height_m](double x, double y) {
      return std::abs(x) <= 0.1 && std::abs(y) <= 0.1 ? height_m : std::nan("");
    });
  };
  const common::GridLayers tall = Truth(kFlat, box(0.15));
  EXPECT_EQ(tall.Layer(kTraversableHeadings)(15, 15), 0.0f);
  EXPECT_EQ(tall.Layer(layers::kTraversability)(15, 15), 1.0f);
  // a low one passes under the belly (0.08 of 0.115 m)
  const PoseAssessment low = At(kFlat, box(0.08), 0.0, 0.0);
  EXPECT_TRUE(low.traversable);
  EXPECT_NEAR(low.belly_m, 0.08, 1e-6);
  EXPECT_NEAR(low.cost, 0.08 / 0.115, 1e-5);
}

TEST(PhysicalTruthTest, EachHeadingsLayerIsItsPose) {
  // rolling ground with a 0.12 m step and a 0.2 m box: every limit in play somewhere
  const Eigen::MatrixXf ground = Sampled([](double x, double y) {
    return 0.1 * std::sin(3.0 * x) * std::cos(2.0 * y) + (x > 1.0 ? 0.12 : 0.0);
  });
  const Eigen::MatrixXf box = Sampled([](double x, double y) {
    return std::abs(x + 1.0) < 0.3 && std::abs(y - 0.5) < 0.2 ? 0.2 : std::nan("");
  });
  const common::GridLayers truth = Truth(ground, box);
  const RestingSurface surface{kWorld, ground, kWorld, box};
  // every cell at every heading: the second half of the headings is looked up as the first half's
  // mirror (ComputePhysicalTruth), the pose here directly
  int known = 0;
  for (int k = 0; k < 16; ++k) {
    for (int mx = 0; mx < kMap.num_x; ++mx) {
      for (int my = 0; my < kMap.num_y; ++my) {
        const PoseAssessment pose =
            AssessPose(surface, kMap.CellCenter(mx, my), 2.0 * M_PI * k / 16.0, RestingBody{},
                       GroundTruthConfig{});
        const float cost = truth.Layer(HeadingLayer(k))(mx, my);
        if (!pose.known) {
          EXPECT_TRUE(std::isnan(cost)) << "heading " << k << " cell " << mx << "," << my;
          continue;
        }
        ++known;
        EXPECT_FLOAT_EQ(cost, static_cast<float>(pose.cost))
            << "heading " << k << " cell " << mx << "," << my;
      }
    }
  }
  EXPECT_EQ(known, 16 * 25 * 25);  // of 30 x 30 cells: the wheels reach 0.42 m from the centre
}

TEST(PhysicalTruthTest, AnOddNumberOfHeadingsIsLookedUpHeadingByHeading) {
  // 3 headings have no pairs half a turn apart: each is its own pose (no mirror)
  const Eigen::MatrixXf ground = Sampled([](double x, double y) {
    return 0.1 * std::sin(3.0 * x) * std::cos(2.0 * y) + (x > 1.0 ? 0.12 : 0.0);
  });
  GroundTruthConfig config;
  config.headings = 3;
  const RestingSurface surface{kWorld, ground, kWorld, kNoObstacles};
  const common::GridLayers truth = ComputePhysicalTruth(kMap, surface, RestingBody{}, config);
  int known = 0;
  for (int k = 0; k < 3; ++k) {
    for (int mx = 0; mx < kMap.num_x; ++mx) {
      for (int my = 0; my < kMap.num_y; ++my) {
        const PoseAssessment pose = AssessPose(surface, kMap.CellCenter(mx, my),
                                               2.0 * M_PI * k / 3.0, RestingBody{}, config);
        if (!pose.known) continue;
        ++known;
        EXPECT_EQ(truth.Layer(HeadingLayer(k))(mx, my), static_cast<float>(pose.cost))
            << "heading " << k << " cell " << mx << "," << my;
      }
    }
  }
  EXPECT_EQ(known, 3 * 25 * 25);
}

TEST(PhysicalTruthTest, TheTruthAtListedCellsIsTheWholeGridsThereAndUnknownElsewhere) {
  // rough ground with a step and a box: every layer's value at a listed cell is the whole grid's
  const Eigen::MatrixXf ground = Sampled([](double x, double y) {
    return 0.1 * std::sin(3.0 * x) * std::cos(2.0 * y) + (x > 1.0 ? 0.12 : 0.0);
  });
  const Eigen::MatrixXf obstacles = Sampled([](double x, double y) {
    return std::abs(x + 1.0) < 0.3 && std::abs(y) < 0.3 ? 0.2 : std::nan("");
  });
  const common::GridLayers whole = Truth(ground, obstacles);
  // a diagonal band, the border cells (unknown in both) and a cell twice
  std::vector<Eigen::Vector2i> cells{{0, 0}, {29, 29}, {7, 9}, {7, 9}};
  for (int i = 0; i < kMap.num_x; ++i) cells.emplace_back(i, (i + 3) % kMap.num_y);
  const common::GridLayers listed =
      ComputePhysicalTruth(kMap, cells, RestingSurface{kWorld, ground, kWorld, obstacles},
                           RestingBody{}, GroundTruthConfig{});
  std::vector<bool> is_listed(static_cast<std::size_t>(kMap.num_x * kMap.num_y), false);
  for (const Eigen::Vector2i& cell : cells) is_listed[cell.x() + cell.y() * kMap.num_x] = true;
  ASSERT_EQ(listed.LayerNames(), whole.LayerNames());
  int known = 0;
  for (const std::string& name : whole.LayerNames()) {
    for (int mx = 0; mx < kMap.num_x; ++mx) {
      for (int my = 0; my < kMap.num_y; ++my) {
        const float value = listed.Layer(name)(mx, my);
        if (!is_listed[mx + my * kMap.num_x]) {
          EXPECT_TRUE(std::isnan(value)) << name << " " << mx << "," << my;
          continue;
        }
        const float expected = whole.Layer(name)(mx, my);
        if (std::isnan(expected)) {
          EXPECT_TRUE(std::isnan(value)) << name << " " << mx << "," << my;
        } else {
          EXPECT_EQ(value, expected) << name << " " << mx << "," << my;
          ++known;
        }
      }
    }
  }
  // on each of the 19 layers: (7, 9) and the band's cells 3 to 24 (the robot fits on cells 3 to
  // 27 along each axis)
  EXPECT_EQ(known, 19 * 23);
  // the band crosses the box: an untraversable cell among traversable ones
  EXPECT_EQ(listed.Layer(layers::kTraversability)(11, 14), 1.0f);
  EXPECT_LT(listed.Layer(layers::kTraversability)(15, 18), 1.0f);
}

}  // namespace
}  // namespace trav::mapping
