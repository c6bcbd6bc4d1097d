#include "mapping/fsgp_bgk_mapper.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "common/random.h"
#include "mapping/features.h"
#include "mapping/window.h"
#include "tests/mapping/mapping_test_util.h"

namespace trav::mapping {
namespace {

using testing::MeanNear;
using testing::RobotAt;
using testing::Surface;

constexpr double kDegToRad = M_PI / 180.0;

TEST(FeaturesTest, FlatGroundHasNoCurvatureOrGradientAndAStepEdgeHasBoth) {
  FsgpConfig config;
  common::Random random(1);
  TrainingSetExtractor extractor;
  const common::PointCloud flat = Surface([](double, double) { return 0.0; }, {0, 0}, 3.0, 0.0);
  const TrainingSet plane = extractor.Extract(flat.points, config, &random);
  EXPECT_LT(plane.curvature.maxCoeff(), 1e-6);
  EXPECT_LT(plane.gradient.maxCoeff(), 1e-6);
  EXPECT_EQ(plane.feature_points, 0);

  const common::PointCloud step =
      Surface([](double x, double) { return x > 0.05 ? 0.2 : 0.0; }, {0, 0}, 3.0, 0.0);
  const TrainingSet edge = extractor.Extract(step.points, config, &random);
  EXPECT_GT(edge.feature_points, 0);
  for (Eigen::Index i = 0; i < edge.points_W.cols(); ++i) {
    const double distance_to_edge = std::abs(edge.points_W(0, i) - 0.05);
    if (distance_to_edge > 0.5) {
      ASSERT_LT(edge.gradient[i], 1e-6) << "at x = " << edge.points_W(0, i);
      ASSERT_LT(edge.curvature[i], 1e-6);
    }
    if (distance_to_edge < 0.1) {
      ASSERT_GT(edge.gradient[i], 0.03);
    }
  }
}

// Every voxel centroid of a cloud (every centroid a training point: no feature voxels, M above the
// count), against a brute-force grouping: the voxels in (z, y, x) order, each the mean of its
// points summed in single precision in the cloud's order; in a window and with points kilometres
// apart.
TEST(FeaturesTest, TheVoxelCentroidsAreABruteForceGroupingsInVoxelOrder) {
  FsgpConfig config;
  config.feature_voxel_m = 0.0;
  config.max_training_points = 100000;
  for (const double spread_m : {5.0, 4.0e5}) {
    common::Random random(7);
    Eigen::Matrix3Xf points(3, 3000);
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
      // clusters of points sharing voxels, some far apart along x and y
      const double far = random.Uniform(0, 1) < 0.3 ? spread_m : 0.0;
      points.col(i) << static_cast<float>(random.Uniform(-1, 1) + far),
          static_cast<float>(random.Uniform(-2, 0.5) - far),
          static_cast<float>(random.Uniform(0, 1));
    }
    const float inverse_voxel = 1.0f / static_cast<float>(config.pre_voxel_m);
    std::map<std::array<std::int64_t, 3>, std::pair<Eigen::Vector3f, int>> voxels;
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
      const Eigen::Vector3f scaled = points.col(i) * inverse_voxel;
      const std::array<std::int64_t, 3> zyx{static_cast<std::int64_t>(std::floor(scaled.z())),
                                            static_cast<std::int64_t>(std::floor(scaled.y())),
                                            static_cast<std::int64_t>(std::floor(scaled.x()))};
      auto& [sum, count] = voxels.try_emplace(zyx, Eigen::Vector3f::Zero(), 0).first->second;
      sum += points.col(i);
      ++count;
    }
    TrainingSetExtractor extractor;
    common::Random sampling(1);
    extractor.ComputeFeatures(points, config);
    const TrainingSet training = extractor.SelectFrom(extractor, config, &sampling);
    ASSERT_EQ(training.pre_voxel_points, static_cast<int>(voxels.size())) << spread_m;
    ASSERT_EQ(training.points_W.cols(), training.pre_voxel_points);
    Eigen::Index c = 0;
    for (const auto& [voxel, centroid] : voxels) {
      const Eigen::Vector3d expected =
          (centroid.first / static_cast<float>(centroid.second)).cast<double>();
      ASSERT_EQ(training.points_W.col(c), expected) << "centroid " << c << ", spread " << spread_m;
      ++c;
    }
  }
}

TEST(FeaturesTest, InverseDistanceWeightsMatchABruteForceSearch) {
  common::Random random(4);
  Eigen::Matrix3Xd training(3, 300);
  for (int j = 0; j < 300; ++j)
    training.col(j) << random.Uniform(-5, 5), random.Uniform(-3, 3), 0.0;
  Eigen::Matrix2Xd queries(2, 200);
  for (int q = 0; q < 200; ++q) queries.col(q) << random.Uniform(-7, 7), random.Uniform(-5, 5);
  InverseDistanceWeighting unlimited, limited;
  unlimited.Compute(training, queries, 5, std::numeric_limits<double>::infinity());
  const double support_radius_m = 0.8;
  limited.Compute(training, queries, 5, support_radius_m);
  const auto indices = unlimited.indices();
  const auto weights = unlimited.weights();
  const auto nearest = unlimited.nearest_m();
  const auto supported_indices = limited.indices();
  const auto supported_weights = limited.weights();
  const auto supported_nearest = limited.nearest_m();
  int unsupported = 0;
  for (int q = 0; q < 200; ++q) {
    std::vector<std::pair<double, int>> all;
    for (int j = 0; j < 300; ++j)
      all.emplace_back((training.col(j).head<2>() - queries.col(q)).norm(), j);
    std::sort(all.begin(), all.end());
    for (int j = 0; j < 5; ++j)
      ASSERT_EQ(indices(j, q), all[static_cast<std::size_t>(j)].second) << "query " << q;
    EXPECT_DOUBLE_EQ(nearest[q], all[0].first);
    EXPECT_NEAR(weights.col(q).sum(), 1.0, 1e-12);
    EXPECT_GT(weights(0, q), weights(4, q));
    // with a support radius: the same answer within it, none beyond
    if (all[0].first <= support_radius_m) {
      EXPECT_EQ(supported_indices.col(q), indices.col(q)) << "query " << q;
      EXPECT_EQ(supported_weights.col(q), weights.col(q)) << "query " << q;
      EXPECT_EQ(supported_nearest[q], nearest[q]);
    } else {
      ++unsupported;
      EXPECT_EQ(supported_nearest[q], std::numeric_limits<double>::infinity()) << "query " << q;
      EXPECT_TRUE((supported_indices.col(q).array() == -1).all()) << "query " << q;
      EXPECT_TRUE((supported_weights.col(q).array() == 0.0).all()) << "query " << q;
    }
  }
  EXPECT_GT(unsupported, 40);  // the queries reach 2 m beyond the training points
}

TEST(CropWindowTest, KeepsTheWindowAndOnlyTheFootOfTallStructures) {
  std::vector<Eigen::Vector3f> points;
  for (double x = -6.0; x <= 6.0; x += 0.25)
    points.emplace_back(static_cast<float>(x), 0.0f, 0.0f);  // floor
  for (int k = 0; k <= 20; ++k)
    points.emplace_back(2.1f, 0.0f, 0.1f * static_cast<float>(k) + 0.05f);  // a wall
  points.emplace_back(std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f);
  MapUpdateResult result;
  WindowCrop dut;
  dut.Crop(common::MakePointCloud(points), Eigen::Vector3d(0, 0, 0.1), 10.0, 1.0, 0.3, &result);
  const auto kept = dut.window();
  EXPECT_EQ(result.dropped_invalid, 1);
  for (Eigen::Index i = 0; i < kept.cols(); ++i) {
    EXPECT_LE(std::abs(kept(0, i)), 5.0f);
    EXPECT_LE(kept(2, i), 0.3f + 1e-6f);
  }
  // the floor inside the window (41 points) and the wall's foot: 0.05, 0.15 and 0.25 m above its
  // lowest point, which stands for the ground of its column (the floor at x = 2.0 and 2.25 is
  // lower)
  EXPECT_EQ(kept.cols(), 41 + 3);
  EXPECT_EQ(result.window_points, 44);
}

TEST(CropWindowTest, KeepsASlopeWholeAndCropsAWallOnIt) {
  // a 30 deg slope along x every 0.1 m: it rises 0.58 m across a 1 m column, so a crop at 0.3 m
  // above each column's lowest point alone cut the upper part of every column away
  const double rise = std::tan(30.0 * M_PI / 180.0);
  std::vector<Eigen::Vector3f> points;
  for (int ix = -49; ix <= 49; ++ix) {
    for (int iy = -49; iy <= 49; ++iy) {
      points.emplace_back(0.1f * static_cast<float>(ix), 0.1f * static_cast<float>(iy),
                          static_cast<float>(rise * 0.1 * ix));
    }
  }
  const Eigen::Index slope_points = static_cast<Eigen::Index>(points.size());
  // a wall face at x = 2.05 standing on the slope, a point every 0.1 m from 0.05 to 1.45 m up
  for (int k = 0; k < 15; ++k) {
    points.emplace_back(2.05f, 0.55f, static_cast<float>(rise * 2.05 + 0.05 + 0.1 * k));
  }
  MapUpdateResult result;
  WindowCrop dut;
  dut.Crop(common::MakePointCloud(points), Eigen::Vector3d(0, 0, 0.1), 10.0, 10.0, 0.3, &result);
  // every point of the slope and the wall's foot (0.05, 0.15, 0.25 m up): the ground there is
  // the plane through the columns' lowest points, which all lie on the slope
  EXPECT_EQ(result.window_points, slope_points + 3);
  const auto kept = dut.window();
  for (Eigen::Index i = 0; i < kept.cols(); ++i) {
    EXPECT_LE(kept(2, i), rise * kept(0, i) + 0.3 + 1e-5) << kept.col(i).transpose();
  }
}

// The robot stands at the mouth of a gap between two walls: within the sensor's blind zone no
// ground shows, so the crop's ground there was the walls' lowest points, where the lowest beam
// met them 0.2 m up, and their lowest 0.5 m passed as terrain; the regression then spread their
// height, curvature and gradient over the gap's cells until A* found no way through
// (`hard/tight_gaps`). Against the cells' floor only their lowest 0.3 m stays.
TEST(CropWindowTest, DropsThePointsStandingAboveTheirCellsFloor) {
  const double rise = std::tan(30.0 * M_PI / 180.0);
  std::vector<Eigen::Vector3f> points;
  for (int k = 0; k < 10; ++k) {
    const float z = 0.2f + 0.05f * static_cast<float>(k);
    points.emplace_back(1.05f, 0.05f, z);   // a wall face seen from close by, from 0.2 m up
    points.emplace_back(-1.05f, 0.05f, z);  // a face in a cell never seen before
  }
  // a 30 deg slope along x at y = 2 (the ground plane rises across the cells)
  for (int ix = -40; ix <= 40; ++ix) {
    points.emplace_back(0.05f * static_cast<float>(ix), 2.05f,
                        static_cast<float>(rise * 0.05 * ix));
  }
  MapUpdateResult result;
  WindowCrop dut;
  dut.Crop(common::MakePointCloud(points), Eigen::Vector3d(0, 0, 0.3), 10.0, 1.0, 0.3, &result);
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(8, 8), 0.2),
      layers::All());
  Eigen::MatrixXf& floor = map.Layer(layers::kFloor);
  const Eigen::Vector2i wall = *map.geometry().CellIndex({1.05, 0.05});
  floor(wall.x(), wall.y()) = 0.0f;  // its foot, seen from afar
  // the slope's cells: their lowest edge
  for (double x = -2.0; x < 2.0; x += 0.2) {
    const Eigen::Vector2i cell = *map.geometry().CellIndex({x + 0.1, 2.05});
    floor(cell.x(), cell.y()) =
        static_cast<float>(rise * (map.geometry().CellCenter(cell.x(), cell.y()).x() - 0.1));
  }
  // the crop's points per cell
  const auto count = [&](const WindowCrop& crop, const Eigen::Vector2d& p_W) {
    const Eigen::Vector2i cell = *map.geometry().CellIndex(p_W);
    int n = 0;
    for (Eigen::Index i = 0; i < crop.window().cols(); ++i) {
      n += map.geometry().CellIndex(crop.window().col(i).head<2>().cast<double>()) == cell;
    }
    return n;
  };
  const Eigen::Index cropped = dut.window().cols();
  const int on_wall = count(dut, {1.05, 0.05}), unseen = count(dut, {-1.05, 0.05});
  ASSERT_GT(on_wall, 0);
  ASSERT_GT(unseen, 0);
  dut.KeepNearFloor(map, 0.3);
  // the face's points more than 0.3 m above its floor go (0.35 to 0.5 m up: four), those at 0.2,
  // 0.25 and 0.3 m stay; the unseen cell's and the slope's stay
  EXPECT_EQ(on_wall, 7);
  EXPECT_EQ(count(dut, {1.05, 0.05}), 3);
  for (Eigen::Index i = 0; i < dut.window().cols(); ++i) {
    if (dut.window()(0, i) > 1.0f && dut.window()(1, i) < 0.2f) {
      EXPECT_LE(dut.window()(2, i), 0.3f + 1e-6f);
    }
  }
  EXPECT_EQ(count(dut, {-1.05, 0.05}), unseen);
  EXPECT_EQ(dut.window().cols(), cropped - 4);
  // an infinite height drops nothing
  WindowCrop level;
  level.Crop(common::MakePointCloud(points), Eigen::Vector3d(0, 0, 0.3), 10.0, 1.0, 0.3, &result);
  level.KeepNearFloor(map, std::numeric_limits<double>::infinity());
  EXPECT_EQ(level.window().cols(), cropped);
}

TEST(ObstacleCellsTest, AFaceAboveItsNeighbourhoodIsAnObstacleAndASlopeIsNot) {
  const common::GridGeometry g =
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(2, 2), 0.2);
  std::vector<Eigen::Vector3f> points;
  // a 20 deg slope along x, sampled every 5 cm
  for (double x = -1.0; x <= 1.0; x += 0.05) {
    for (double y = -1.0; y <= 1.0; y += 0.05) {
      points.emplace_back(static_cast<float>(x), static_cast<float>(y),
                          static_cast<float>(std::tan(20.0 * M_PI / 180.0) * x));
    }
  }
  // two sparse points high on a wall face in the cell at (0.4, 0.4): 0.9 and 1.0 m up
  const float base = static_cast<float>(std::tan(20.0 * M_PI / 180.0) * 0.4);
  points.emplace_back(0.41f, 0.4f, base + 0.9f);
  points.emplace_back(0.42f, 0.39f, base + 1.0f);
  const Eigen::Matrix3Xf cloud = common::MakePointCloud(points).points;
  const Eigen::Vector2i low(0, 0), high(g.num_x - 1, g.num_y - 1);
  ObstacleMarker marker;
  const Eigen::MatrixXf dut = marker.Cells(cloud, g, low, high, 0.3, 0.15, 0.0);
  const Eigen::Vector2i wall = *g.CellIndex({0.4, 0.4});
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      EXPECT_EQ(dut(ix, iy), (Eigen::Vector2i(ix, iy) == wall) ? 1.0f : 0.0f) << ix << "," << iy;
    }
  }
  // no points: unknown
  EXPECT_TRUE(std::isnan(marker.Cells(Eigen::Matrix3Xf(3, 0), g, low, high, 0.3, 0.15, 0.0)(3, 3)));
}

TEST(ObstacleCellsTest, AboveTheCropsGroundPlaneASteepSlopeIsNoFaceAndAWallOnItIs) {
  // a 35 deg slope along the diagonal, every 5 cm, and a 0.5 m wall face on it at x = 1.05
  const common::GridGeometry g =
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(4, 4), 0.2);
  const double rise = std::tan(35.0 * M_PI / 180.0) / std::sqrt(2.0);  // along x and along y
  auto ground_z = [&](double x, double y) { return rise * (x + y); };
  std::vector<Eigen::Vector3f> points;
  for (int ix = -40; ix < 40; ++ix) {
    for (int iy = -40; iy < 40; ++iy) {
      const double x = 0.05 * ix, y = 0.05 * iy;
      points.emplace_back(static_cast<float>(x), static_cast<float>(y),
                          static_cast<float>(ground_z(x, y)));
    }
  }
  for (int iy = -9; iy <= 9; ++iy) {
    for (int k = 1; k <= 30; ++k) {
      const double y = 0.05 * iy;
      points.emplace_back(1.05f, static_cast<float>(y),
                          static_cast<float>(ground_z(1.05, y) + 0.05 * k));
    }
  }
  const common::PointCloud cloud = common::MakePointCloud(points);
  MapUpdateResult result;
  WindowCrop crop;
  crop.Crop(cloud, Eigen::Vector3d(0, 0, 0.1), 4.0, 10.0, 0.3, &result);
  EXPECT_NEAR(crop.GroundGradient({0.3, -0.6}).x(), rise, 1e-5);
  EXPECT_NEAR(crop.GroundGradient({0.3, -0.6}).y(), rise, 1e-5);
  const Eigen::Vector2i low(0, 0), high(g.num_x - 1, g.num_y - 1);
  ObstacleMarker marker;
  const Eigen::MatrixXf dut = marker.Cells(cloud.points, g, low, high, 0.3, 0.15, 0.0, &crop);
  // the wall's cells (x = 1.0, y = -0.4 to 0.4) and no other
  int faces = 0;
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      if (std::isnan(dut(ix, iy))) continue;
      const Eigen::Vector2d c = g.CellCenter(ix, iy);
      const bool wall = std::abs(c.x() - 1.0) < 1e-9 && std::abs(c.y()) < 0.45;
      EXPECT_EQ(dut(ix, iy), wall ? 1.0f : 0.0f) << c.transpose();
      faces += dut(ix, iy) == 1.0f ? 1 : 0;
    }
  }
  EXPECT_EQ(faces, 5);
  // against the lowest point of the neighbourhood alone the slope itself reads as faces
  const Eigen::MatrixXf level = marker.Cells(cloud.points, g, low, high, 0.3, 0.15, 0.0);
  EXPECT_GT((level.array() == 1.0f).count(), 100);
}

// A platform whose edge stands at x = 0.12 (in the cell of centre 0.2), sampled every 5 cm.
Eigen::Matrix3Xf PlatformCloud(double height_m) {
  std::vector<Eigen::Vector3f> points;
  for (double x = -1.0; x <= 1.0; x += 0.05) {
    for (double y = -1.0; y <= 1.0; y += 0.05) {
      points.emplace_back(static_cast<float>(x), static_cast<float>(y),
                          x >= 0.12 ? static_cast<float>(height_m) : 0.0f);
    }
  }
  return common::MakePointCloud(points).points;
}

TEST(ObstacleCellsTest, AStepHigherThanTheClimbableOneIsAnObstacleHoweverLow) {
  const common::GridGeometry g =
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(2, 2), 0.2);
  const Eigen::Vector2i low(0, 0), high(g.num_x - 1, g.num_y - 1);
  ObstacleMarker marker;
  // a 0.25 m platform, lower than the 0.3 m face test: the step test marks its edge cells (its
  // top 0.25 m above the cell before the edge), nothing else
  const Eigen::MatrixXf platform = marker.Cells(PlatformCloud(0.25), g, low, high, 0.3, 0.15, 0.0);
  const int edge = g.CellIndex({0.2, 0.0})->x();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      EXPECT_EQ(platform(ix, iy), ix == edge ? 1.0f : 0.0f) << ix << "," << iy;
    }
  }
  // without the step test, or for a 0.10 m curb, nothing
  EXPECT_EQ(marker.Cells(PlatformCloud(0.25), g, low, high, 0.3, 0.0, 0.0).maxCoeff(), 0.0f);
  EXPECT_EQ(marker.Cells(PlatformCloud(0.10), g, low, high, 0.3, 0.15, 0.0).maxCoeff(), 0.0f);
  // but the curb's roughness: half its height on the cells either side of its edge, 0 elsewhere
  const Eigen::MatrixXf roughness = marker.roughness();
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const bool beside = ix == edge || ix == edge - 1;
      EXPECT_NEAR(roughness(ix, iy), beside ? 0.05f : 0.0f, 1e-6) << ix << "," << iy;
    }
  }
}

// A wall 0.45 m high, 1 m ahead of a sensor 0.32 m above the ground: the lowest beam (7 deg down)
// meets its face 0.2 m up, and the ground before it lies in the blind zone, so its points span
// 0.2 to 0.45 m with nothing lower beside them. Seen so (found on the suite's ruin at seed 208,
// where the robot drove into such a wall), only the vertical extent within the cell shows the face.
TEST(ObstacleCellsTest, ALowWallSeenFromCloseByIsAnObstacleThoughItsFootIsHidden) {
  const common::GridGeometry g =
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(4, 4), 0.2);
  std::vector<Eigen::Vector3f> points;
  for (double y = -1.0; y <= 1.0; y += 0.05) {
    for (double z = 0.2; z <= 0.45 + 1e-9; z += 0.05) {
      points.emplace_back(1.01f, static_cast<float>(y), static_cast<float>(z));
    }
    // its top, 0.2 m thick
    for (double x = 1.05; x <= 1.2; x += 0.05) {
      points.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.45f);
    }
  }
  const Eigen::Matrix3Xf cloud = common::MakePointCloud(points).points;
  const Eigen::Vector2i low(0, 0), high(g.num_x - 1, g.num_y - 1);
  ObstacleMarker marker;
  const Eigen::MatrixXf dut = marker.Cells(cloud, g, low, high, 0.3, 0.15, 0.0);
  const int face = g.CellIndex({1.01, 0.0})->x();
  const int first = g.CellIndex({0.0, -0.9})->y(), last = g.CellIndex({0.0, 0.9})->y();
  for (int iy = first; iy <= last; ++iy) {
    EXPECT_EQ(dut(face, iy), 1.0f) << iy;
    EXPECT_EQ(dut(face + 1, iy), 0.0f) << iy;  // the top alone: no face
  }
  // without the step test the 0.25 m of face seen is no obstacle: the robot drove into it
  const Eigen::MatrixXf without = marker.Cells(cloud, g, low, high, 0.3, 0.0, 0.0);
  EXPECT_EQ(without(face, g.CellIndex({0.0, 0.0})->y()), 0.0f);

  // the wall met obliquely: the lowest beam meets its face at heights that differ from cell to
  // cell along it (here by 1.5 cm, alternately), so that most cells have a neighbour with a lower
  // point; each cell's own span still marks it (`hard/low_wall` hit the wall so with a 0.15 m
  // clearance)
  std::vector<Eigen::Vector3f> oblique;
  for (const Eigen::Vector3f& p : points) {
    const bool raised = p.x() < 1.02f && g.CellIndex({p.x(), p.y()})->y() % 2 == 1;
    oblique.emplace_back(p.x(), p.y(), raised ? std::max(p.z(), 0.215f) : p.z());
  }
  const Eigen::MatrixXf scattered =
      marker.Cells(common::MakePointCloud(oblique).points, g, low, high, 0.3, 0.15, 0.0);
  for (int iy = first; iy <= last; ++iy) EXPECT_EQ(scattered(face, iy), 1.0f) << iy;

  // rubble on a slope: a cell whose points span 0.16 m beside a cell whose ground lies lower (its
  // foot is seen) is no face; without the condition on the lowest point it closed a gap of the
  // suite's ruin at seed 109
  std::vector<Eigen::Vector3f> rubble;
  for (double z = 0.0; z <= 0.16 + 1e-9; z += 0.02) rubble.emplace_back(1.05f, 0.05f, z);
  for (double z = -0.05; z <= 0.05 + 1e-9; z += 0.05) rubble.emplace_back(0.85f, 0.05f, z);
  const Eigen::MatrixXf slope =
      marker.Cells(common::MakePointCloud(rubble).points, g, low, high, 0.3, 0.15, 0.0);
  const Eigen::Vector2i spanning = *g.CellIndex({1.05, 0.05}), lower = *g.CellIndex({0.85, 0.05});
  EXPECT_EQ(slope(spanning.x(), spanning.y()), 0.0f);
  EXPECT_EQ(slope(lower.x(), lower.y()), 0.0f);
}

// Ground every 5 cm with a block 0.3 x 0.3 m and `height_m` high centred at (1.1, 0) on it.
Eigen::Matrix3Xf BlockCloud(double height_m) {
  std::vector<Eigen::Vector3f> points;
  for (int ix = -39; ix <= 39; ++ix) {
    for (int iy = -39; iy <= 39; ++iy) {
      const double x = 0.05 * ix + 0.01, y = 0.05 * iy + 0.01;
      const bool raised = std::abs(x - 1.1) < 0.15 && std::abs(y) < 0.15;
      points.emplace_back(static_cast<float>(x), static_cast<float>(y),
                          raised ? static_cast<float>(height_m) : 0.0f);
    }
  }
  return common::MakePointCloud(points).points;
}

// Rubble 0.12 m high and 0.3 m wide passes between the Scout Mini's wheels and meets its chassis
// (0.115 m clear): `probes/ruin_dense` at seed 1 and `suite/ruin` at seed 105 ended on such a
// piece. It is marked; a curb as high (ground as high on one side), a block lower than the bump
// limit and the block without the test are not (nor any of them as a step or a face).
TEST(ObstacleCellsTest, ABumpTheChassisWouldStraddleIsAnObstacleAndACurbIsNot) {
  const common::GridGeometry g =
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(4, 4), 0.2);
  const Eigen::Vector2i low(0, 0), high(g.num_x - 1, g.num_y - 1);
  ObstacleMarker marker;
  const Eigen::MatrixXf rubble = marker.Cells(BlockCloud(0.12), g, low, high, 0.3, 0.15, 0.1);
  int bumps = 0;
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const Eigen::Vector2d c = g.CellCenter(ix, iy);
      // the cells holding the block's points: two along x, three along y
      const bool on_block = c.x() > 0.85 && c.x() < 1.35 && std::abs(c.y()) < 0.25;
      EXPECT_EQ(rubble(ix, iy), on_block ? 1.0f : 0.0f) << c.transpose();
      bumps += on_block;
    }
  }
  EXPECT_EQ(bumps, 6);
  // no obstacle (cells without points are NaN): a 0.12 m curb from x = 0.12 on, a 0.09 m block,
  // the 0.12 m block without the test
  const auto obstacles = [&](const Eigen::Matrix3Xf& cloud, double max_bump_m) {
    return (marker.Cells(cloud, g, low, high, 0.3, 0.15, max_bump_m).array() == 1.0f).count();
  };
  EXPECT_EQ(obstacles(PlatformCloud(0.12), 0.1), 0);
  EXPECT_EQ(obstacles(BlockCloud(0.09), 0.1), 0);
  EXPECT_EQ(obstacles(BlockCloud(0.12), 0.0), 0);
}

TEST(FsgpBgkMapperTest, AWallIsUntraversableAndItsCellsClearWhenSeenFree) {
  FsgpBgkMapper dut(FsgpConfig{});
  common::PointCloud scan = Surface([](double, double) { return 0.0; }, {0, 0});
  std::vector<Eigen::Vector3f> with_wall;
  for (Eigen::Index i = 0; i < scan.size(); ++i) with_wall.emplace_back(scan.points.col(i));
  for (double y = -1.0; y <= 1.0; y += 0.1) {
    for (double z = 0.0; z <= 1.5; z += 0.1) {
      with_wall.emplace_back(2.0f, static_cast<float>(y), static_cast<float>(z));
    }
  }
  ASSERT_EQ(dut.Update(common::MakePointCloud(with_wall), RobotAt(0, 0), 0.0).status,
            MapUpdateStatus::kUpdated);
  const Eigen::Vector2d wall_W(2.0, 0.0);
  EXPECT_EQ(*dut.map().At(layers::kTraversability, wall_W), 1.0f);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, wall_W), 1.0f);
  EXPECT_LT(*dut.map().At(layers::kTraversability, {-2.0, 0.0}), 0.1f);
  // the wall is gone (a mover walked away): the next frame of bare ground clears it
  ASSERT_EQ(dut.Update(scan, RobotAt(0, 0), 0.1).status, MapUpdateStatus::kUpdated);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, wall_W), 0.0f);
  EXPECT_LT(*dut.map().At(layers::kTraversability, wall_W), 0.5f);
}

// A robot pitched up (on rubble) whose lowest beam rises sees the top of a low wall ahead and no
// ground before it. `hard/low_wall` at LiDAR seeds 14 and 17 took the top for ground (the
// regression raised the mapped elevation there to the top's height), so the cells showed no face
// and cleared the wall seen before, and the robot drove into it. A cell's floor, the lowest point
// it ever showed, keeps the ground where it was seen.
TEST(ObstacleCellsTest, ALowWallWhoseTopAloneIsSeenStaysAnObstacle) {
  const MapArea area = FsgpConfig{}.area;
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(12, 12), 0.2),
      layers::All());
  const Eigen::Vector3d p_WB(0.0, 0.0, 0.3);
  const auto [low, high] = WindowCells(map.geometry(), p_WB, area.window_m);
  const common::PointCloud ground = Surface([](double, double) { return 0.0; }, {0, 0});
  const common::PointCloud top = Surface([](double, double) { return 0.45; }, {0, 0});
  // first its face, 0.45 m high, the ground before it and its top
  std::vector<Eigen::Vector3f> faced, top_only;
  for (Eigen::Index i = 0; i < ground.size(); ++i) {
    const bool before = ground.points(0, i) < 2.0f;
    if (before) faced.emplace_back(ground.points.col(i));
    if (!before) faced.emplace_back(top.points.col(i));
    // then only the top ahead and the ground behind the robot
    if (ground.points(0, i) < -2.5f) top_only.emplace_back(ground.points.col(i));
    if (!before) top_only.emplace_back(top.points.col(i));
  }
  for (double y = -1.0; y <= 1.0; y += 0.05) {
    for (double z = 0.0; z <= 0.45 + 1e-9; z += 0.05) {
      faced.emplace_back(2.01f, static_cast<float>(y), static_cast<float>(z));
    }
  }
  WindowCrop crop;
  ObstacleMarker marker;
  MapUpdateResult result;
  const auto mark = [&](const std::vector<Eigen::Vector3f>& points, double t_s) {
    crop.Crop(common::MakePointCloud(points), p_WB, area.window_m, area.max_height_above_robot_m,
              area.GroundCropHeight(), &result);
    marker.Mark(crop, low, high, area, p_WB, t_s, 2, &map);
  };
  mark(faced, 0.0);
  const Eigen::Vector2d face_W(2.01, 0.0), top_W(2.5, 0.0);
  ASSERT_EQ(map.At(layers::kObstacle, face_W), 1.0f);
  EXPECT_EQ(map.At(layers::kObstacle, top_W), 0.0f);
  EXPECT_NEAR(map.At(layers::kFloor, face_W).value_or(1.0f), 0.0, 0.01);
  // the regression took the top for the ground there
  map.Layer(layers::kElevation).setConstant(0.45f);
  mark(top_only, 0.1);
  EXPECT_EQ(map.At(layers::kObstacle, face_W), 1.0f);
  EXPECT_EQ(map.At(layers::kTraversability, face_W), 1.0f);
  EXPECT_NEAR(map.At(layers::kFloor, face_W).value_or(1.0f), 0.0, 0.01);
  // the top's own cells, whose floor is the top, show no face
  EXPECT_EQ(map.At(layers::kObstacle, top_W), 0.0f);
}

// A 12 x 12 m map at 0.2 m after ObstacleMarker::Mark of each (time, points) in turn, cropped as
// the default area crops them, the robot at p_WB.
common::GridLayers MarkedMap(const Eigen::Vector3d& p_WB,
                             const std::vector<std::pair<double, common::PointCloud>>& frames) {
  const MapArea area = FsgpConfig{}.area;
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(12, 12), 0.2),
      layers::All());
  const auto [low, high] = WindowCells(map.geometry(), p_WB, area.window_m);
  WindowCrop crop;
  ObstacleMarker marker;
  MapUpdateResult result;
  for (const auto& [t_s, points] : frames) {
    crop.Crop(points, p_WB, area.window_m, area.max_height_above_robot_m, area.GroundCropHeight(),
              &result);
    marker.Mark(crop, low, high, area, p_WB, t_s, 2, &map);
  }
  return map;
}

// A low wall 0.25 m high (above the 0.15 m step the robot climbs, below the 0.3 m face test), seen
// first from afar with the ground before it, then from close by, when that ground lies in the blind
// zone and the lowest beam meets its face 0.12 m up: the close frames show 0.13 m of face and no
// ground beside it. `probes` ruins (terrain seed 913) hid the foot of such a wall behind a mound
// until the robot was close, cleared it, and the robot drove into it at 1 m/s. The cell's floor,
// the ground it showed before, keeps it a step, and the top's cells are a step above it; a 0.12 m
// curb seen so stays free.
TEST(ObstacleCellsTest, ALowWallWhoseFootWasSeenBeforeStaysAStepSeenFromCloseBy) {
  const Eigen::Vector3d p_WB(0.0, 0.0, 0.3);
  const common::PointCloud ground = Surface([](double, double) { return 0.0; }, {0, 0});
  // the wall's face at x = 2.01 from `foot_m` up to its top, its top 0.26 m deep behind it, and
  // the ground before it up to `before_m` ahead of the robot (the rest of the ground hidden)
  const auto frame = [&](double height_m, double foot_m, double before_m) {
    std::vector<Eigen::Vector3f> points;
    for (Eigen::Index i = 0; i < ground.size(); ++i) {
      const float x = ground.points(0, i);
      if (x < -2.5f || (x >= 0.0f && x < before_m)) points.emplace_back(ground.points.col(i));
    }
    for (double y = -1.0; y <= 1.0; y += 0.05) {
      for (double z = foot_m; z <= height_m + 1e-9; z += 0.025) {
        points.emplace_back(2.01f, static_cast<float>(y), static_cast<float>(z));
      }
      for (double x = 2.05; x <= 2.26; x += 0.05) {
        points.emplace_back(static_cast<float>(x), static_cast<float>(y),
                            static_cast<float>(height_m));
      }
    }
    return common::MakePointCloud(points);
  };
  // the cells centred at x = 1.8 (ground), 2.0 (the face and the top's first 5 cm), 2.2 (the top)
  const Eigen::Vector2d before_W(1.8, 0.0), face_W(2.0, 0.0), top_W(2.2, 0.0);
  const auto obstacle_after = [&](double height_m) {
    // from afar: the face down to the ground before it; then from close by, twice
    const common::GridLayers map = MarkedMap(p_WB, {{0.0, frame(height_m, 0.0, 2.0)},
                                                    {0.1, frame(height_m, 0.12, 0.0)},
                                                    {0.7, frame(height_m, 0.12, 0.0)}});
    EXPECT_NEAR(map.At(layers::kFloor, before_W).value_or(1.0f), 0.0, 0.01) << height_m;
    return std::pair{map.At(layers::kObstacle, face_W).value_or(-1.0f),
                     map.At(layers::kObstacle, top_W).value_or(-1.0f)};
  };
  // the face's cell, and the top's, whose floor (the top) stands as high above the face cell's
  EXPECT_EQ(obstacle_after(0.25), std::pair(1.0f, 1.0f));
  EXPECT_EQ(obstacle_after(0.12), std::pair(0.0f, 0.0f));
}

// A box leaning over the robot's way: the cells along its lower edge show only its face from
// 0.33 m up, never the ground under the overhang; the ground before them was seen from farther
// away and is in the blind zone now. `hard/low_wall` at LiDAR seed 4 (with the exact distances to
// the faces' boxes) read such cells free and drove into the box at 0.9 m/s. A cell whose floor
// stands above a side neighbour's by more than the climbable step is a step; a box top 0.12 m up
// is not.
TEST(ObstacleCellsTest, ACellThatNeverShowedItsGroundIsAStepAboveTheGroundBesideIt) {
  const Eigen::Vector3d p_WB(0.0, 0.0, 0.3);
  const common::PointCloud ground = Surface([](double, double) { return 0.0; }, {0, 0});
  // the ground up to x = 2 (the whole frame's or behind the robot only), and the face's points
  // between `low_m` and `high_m` at x = 2.01 to 2.09 (the cell centred at x = 2.0 holds x = 1.9 to
  // 2.1 and the ground up to 2.0 the first time; the cell centred at 2.2 no point)
  const auto frame = [&](bool ground_before, double low_m, double high_m) {
    std::vector<Eigen::Vector3f> points;
    for (Eigen::Index i = 0; i < ground.size(); ++i) {
      const float x = ground.points(0, i);
      if (x < -2.5f || (ground_before && x < 1.85f)) points.emplace_back(ground.points.col(i));
    }
    for (double y = -1.0; y <= 1.0; y += 0.05) {
      for (double x = 2.01; x <= 2.09; x += 0.04) {
        for (double z = low_m; z <= high_m + 1e-9; z += 0.03) {
          points.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
        }
      }
    }
    return common::MakePointCloud(points);
  };
  const Eigen::Vector2d before_W(1.8, 0.0), face_W(2.0, 0.0);
  const auto obstacle_after = [&](double low_m, double high_m) {
    const common::GridLayers map =
        MarkedMap(p_WB, {{0.0, frame(true, low_m, high_m)}, {0.1, frame(false, low_m, high_m)}});
    EXPECT_NEAR(map.At(layers::kFloor, before_W).value_or(1.0f), 0.0, 0.01);
    EXPECT_NEAR(map.At(layers::kFloor, face_W).value_or(1.0f), low_m, 1e-6);
    return map.At(layers::kObstacle, face_W).value_or(-1.0f);
  };
  EXPECT_EQ(obstacle_after(0.33, 0.45), 1.0f);
  EXPECT_EQ(obstacle_after(0.09, 0.12), 0.0f);
}

// A doorway's jamb, 2 m high, ends at x = 2.11, a centimetre into the cells centred at x = 2.2;
// the robot in the doorway sees the ground before it no more (the blind zone), and range noise puts
// a few of the jamb's points 2 cm into the cell centred at 2.0, whose floor was seen before at 0
// (`probes/indoor_across` at seed 1: that cell became a whole cell of jamb, the 1 m door read
// 0.67 m wide and the robot stopped in it for good). Those points stand more than the crop height
// above the cell's floor: a tall face, bounded by its points, not the whole cell.
TEST(ObstacleCellsTest, AJambsEndSeenInACellWhoseGroundWasSeenBeforeIsBoundedByItsPoints) {
  const Eigen::Vector3d p_WB(0.0, 0.0, 0.3);
  const common::PointCloud ground = Surface([](double, double) { return 0.0; }, {0, 0});
  // the ground before the jamb (or behind the robot only), the jamb's end face from 0.3 m up at
  // x = 2.11 and `spill` points of it at x = 2.09
  const auto frame = [&](bool ground_before, bool spill) {
    std::vector<Eigen::Vector3f> points;
    for (Eigen::Index i = 0; i < ground.size(); ++i) {
      const float x = ground.points(0, i);
      if (x < -2.5f || (ground_before && x < 2.1f)) points.emplace_back(ground.points.col(i));
    }
    for (double y = -1.0; y <= 1.0; y += 0.05) {
      for (double z = 0.3; z <= 2.0; z += 0.05) {
        points.emplace_back(2.11f, static_cast<float>(y), static_cast<float>(z));
      }
      if (!spill) continue;
      for (double z = 0.3; z <= 0.45; z += 0.05) {
        points.emplace_back(2.09f, static_cast<float>(y), static_cast<float>(z));
      }
    }
    return common::MakePointCloud(points);
  };
  const common::GridLayers map =
      MarkedMap(p_WB, {{0.0, frame(true, false)}, {0.1, frame(false, true)}});
  const Eigen::Vector2i spilled = *map.geometry().CellIndex({2.0, 0.0});
  EXPECT_EQ(map.At(layers::kObstacle, {2.0, 0.0}), 1.0f);
  EXPECT_NEAR(map.Layer(layers::kFaceXLow)(spilled.x(), spilled.y()), 0.09f, 1e-5f);
  EXPECT_NEAR(map.Layer(layers::kFaceXHigh)(spilled.x(), spilled.y()), 0.09f, 1e-5f);
}

// The end of a 4 cm thick wall 0.45 m high, at x = 2.03 to 2.07 and y = -0.27 to 0.03, fills a
// few centimetres of its 0.2 m cells: the cell centred at (2, 0) holds x = 0.03 to 0.07 and
// y = -0.07 to 0.03 of it. Each face cell keeps the box of its points over its run as a face; the
// cells of a step lower than the crop (the same end 0.2 m high at x = -2) are whole.
TEST(ObstacleCellsTest, AFaceCellKeepsTheBoxOfItsFacesPointsWhileItIsAFace) {
  const MapArea area = FsgpConfig{}.area;
  common::GridLayers map(
      common::GridGeometry::Centered(Eigen::Vector2d::Zero(), Eigen::Vector2d(12, 12), 0.2),
      layers::All());
  const Eigen::Vector3d p_WB(0.0, 0.0, 0.3);
  const auto [low, high] = WindowCells(map.geometry(), p_WB, area.window_m);
  const common::PointCloud ground = Surface([](double, double) { return 0.0; }, {0, 0});
  const auto frame = [&](float far_face_x) {
    std::vector<Eigen::Vector3f> points;
    for (Eigen::Index i = 0; i < ground.size(); ++i) points.emplace_back(ground.points.col(i));
    if (far_face_x > 0.0f) {
      for (int k = 0; k <= 6; ++k) {
        for (int j = 0; j <= 9; ++j) {
          const float y = -0.27f + 0.05f * static_cast<float>(k);
          const float z = 0.05f * static_cast<float>(j);
          points.emplace_back(2.03f, y, z);
          points.emplace_back(far_face_x, y, z);
          if (z <= 0.2f) points.emplace_back(-1.97f, y, z);
        }
      }
    }
    return common::MakePointCloud(points);
  };
  WindowCrop crop;
  ObstacleMarker marker;
  MapUpdateResult result;
  const auto mark = [&](const common::PointCloud& points, double t_s) {
    crop.Crop(points, p_WB, area.window_m, area.max_height_above_robot_m, area.GroundCropHeight(),
              &result);
    marker.Mark(crop, low, high, area, p_WB, t_s, 2, &map);
  };
  // (GridLayers::At reads NaN as no value)
  const auto extent = [&](const Eigen::Vector2d& p_W) {
    const Eigen::Vector2i c = *map.geometry().CellIndex(p_W);
    return Eigen::Vector4f(
        map.Layer(layers::kFaceXLow)(c.x(), c.y()), map.Layer(layers::kFaceXHigh)(c.x(), c.y()),
        map.Layer(layers::kFaceYLow)(c.x(), c.y()), map.Layer(layers::kFaceYHigh)(c.x(), c.y()));
  };
  const Eigen::Vector2d end_W(2.0, 0.0), side_W(2.0, -0.2), ground_W(1.0, 0.0);
  mark(frame(2.07f), 0.0);
  ASSERT_EQ(map.At(layers::kObstacle, end_W), 1.0f);
  ASSERT_EQ(map.At(layers::kObstacle, side_W), 1.0f);
  EXPECT_TRUE(extent(end_W).isApprox(Eigen::Vector4f(0.03f, 0.07f, -0.07f, 0.03f), 1e-5f))
      << extent(end_W).transpose();
  EXPECT_TRUE(extent(side_W).isApprox(Eigen::Vector4f(0.03f, 0.07f, -0.07f, 0.08f), 1e-5f))
      << extent(side_W).transpose();
  EXPECT_EQ(map.At(layers::kObstacle, ground_W), 0.0f);
  EXPECT_TRUE(extent(ground_W).hasNaN());
  const Eigen::Vector2d step_W(-2.0, 0.0);
  EXPECT_EQ(map.At(layers::kObstacle, step_W), 1.0f);
  EXPECT_TRUE(extent(step_W).hasNaN());
  // the far face seen a centimetre farther (range noise): the box grows to hold both
  mark(frame(2.08f), 0.1);
  EXPECT_TRUE(extent(end_W).isApprox(Eigen::Vector4f(0.03f, 0.08f, -0.07f, 0.03f), 1e-5f))
      << extent(end_W).transpose();
  // seen free (the face was no lasting one): no face, no box
  mark(frame(0.0f), 0.2);
  EXPECT_EQ(map.At(layers::kObstacle, end_W), 0.0f);
  EXPECT_TRUE(extent(end_W).hasNaN());
}

// A plateau 1 m high up to x = 2 and ground seen `drop_m` lower from x = 4 on, nothing between
// (every 5 cm for |y| <= 1); both falling along x at `slope_deg`, a hillside.
struct DropWorld {
  explicit DropWorld(double drop_m, double slope_deg = 0.0) {
    std::vector<Eigen::Vector3f> points;
    const double fall = std::tan(slope_deg * M_PI / 180.0);
    for (int iy = -20; iy <= 20; ++iy) {
      for (int ix = 10; ix < 120; ++ix) {
        const double x = 0.05 * ix + (ix >= 40 ? 0.02 : 0.0);
        if (x >= 2.0 && x < 4.0) continue;
        points.emplace_back(static_cast<float>(x), static_cast<float>(0.05 * iy),
                            static_cast<float>((x < 2.0 ? 1.0 : 1.0 - drop_m) - fall * x));
      }
    }
    cloud = common::MakePointCloud(points).points;
  }

  // Drops after Cells over the whole grid.
  Eigen::MatrixXf Drops(const MapArea& area) {
    marker.Cells(cloud, g, low, high, 0.3, 0.15, 0.0);
    return marker.Drops(g, area, p_WB).cast<float>();
  }

  const common::GridGeometry g{
      common::GridGeometry::Centered(Eigen::Vector2d(3, 0), Eigen::Vector2d(8, 4), 0.2)};
  const Eigen::Vector2i low{0, 0}, high{g.num_x - 1, g.num_y - 1};
  Eigen::Matrix3Xf cloud;
  Eigen::Vector3d p_WB{0.0, 0.0, 1.1};  // the robot's base on the plateau
  ObstacleMarker marker;
};

TEST(ObstacleCellsTest, CellsNeverSeenBetweenAnEdgeAndGroundFarBelowItAreADrop) {
  DropWorld world(1.0);
  const MapArea area;  // a drop is deeper than 0.27 m within 3 m
  const Eigen::MatrixXf drops = world.Drops(area);
  int marked = 0;
  for (int ix = 0; ix < world.g.num_x; ++ix) {
    for (int iy = 0; iy < world.g.num_y; ++iy) {
      const Eigen::Vector2d c = world.g.CellCenter(ix, iy);
      const bool gap = c.x() > 2.0 && c.x() < 4.0;
      // along x (y = 0) every cell of the gap is a drop; a cell with points never is, nor one off
      // the lines from the edge to the ground beyond
      if (gap && std::abs(c.y()) < 0.1) {
        EXPECT_EQ(drops(ix, iy), 1.0f) << c.transpose();
      }
      if (!gap || std::abs(c.y()) > 1.1) {
        EXPECT_EQ(drops(ix, iy), 0.0f) << c.transpose();
      }
      marked += drops(ix, iy) == 1.0f ? 1 : 0;
    }
  }
  EXPECT_GT(marked, 20);
  // a point in the gap at the edge's height ends the line through it there: nothing before it on
  // that line is a drop, the other lines are
  const Eigen::Vector2i post = *world.g.CellIndex({3.0, 0.0});
  world.cloud.conservativeResize(3, world.cloud.cols() + 1);
  world.cloud.col(world.cloud.cols() - 1) = Eigen::Vector3f(3.0f, 0.01f, 0.95f);
  const Eigen::MatrixXf with_post = world.Drops(area);
  const Eigen::Vector2i before_post = *world.g.CellIndex({2.2, 0.0});
  const Eigen::Vector2i beside = *world.g.CellIndex({2.2, 0.2});
  EXPECT_EQ(drops(before_post.x(), before_post.y()), 1.0f);
  EXPECT_EQ(with_post(post.x(), post.y()), 0.0f);
  EXPECT_EQ(with_post(before_post.x(), before_post.y()), 0.0f);
  EXPECT_EQ(with_post(beside.x(), beside.y()), 1.0f);
}

TEST(ObstacleCellsTest, NoDropWhereTheGroundBeyondIsNotFarEnoughBelowOrTooFarAway) {
  MapArea area;
  DropWorld shallow(0.2);  // less than the 0.27 m the robot drives down
  EXPECT_EQ(shallow.Drops(area).maxCoeff(), 0.0f);
  DropWorld deep(1.0);
  area.drop_slope_deg = 30.0;  // 1 m over the 2.2 m between edge and ground is 24 deg
  EXPECT_EQ(deep.Drops(area).maxCoeff(), 0.0f);
  area.drop_slope_deg = 20.0;
  area.drop_gap_m = 1.5;  // the gap is 2 m
  EXPECT_EQ(deep.Drops(area).maxCoeff(), 0.0f);
  area.drop_gap_m = 3.0;
  deep.p_WB.z() = 0.1;  // the robot below the plateau: its top is out of reach, no edge
  EXPECT_EQ(deep.Drops(area).maxCoeff(), 0.0f);
  deep.p_WB.z() = 1.1;
  area.drop_gap_m = 0.0;  // no drop test
  EXPECT_EQ(deep.Drops(area).maxCoeff(), 0.0f);
}

// Down a 25 deg hillside the gaps between the points open: 2 m of it unseen falls 0.93 m, more
// than the 0.27 m drop and steeper than the 20 deg drop slope, but no steeper than the ground
// before it (`probes/slope_down`: the robot facing down such a slope marked drops ahead and never
// left its start). A 1 m cliff in the same hillside is still a drop.
TEST(ObstacleCellsTest, AHillsideFallingOnAsBeforeItsGapIsNoDrop) {
  const MapArea area;
  DropWorld hillside(0.0, 25.0);
  EXPECT_EQ(hillside.Drops(area).maxCoeff(), 0.0f);
  DropWorld cliff(1.0, 25.0);
  const Eigen::MatrixXf drops = cliff.Drops(area);
  // the cells centred at x = 2.2 to 3.8, wholly in the gap
  for (int k = 1; k <= 9; ++k) {
    const double x = 2.0 + 0.2 * k;
    const Eigen::Vector2i gap = *cliff.g.CellIndex({x, 0.0});
    EXPECT_EQ(drops(gap.x(), gap.y()), 1.0f) << x;
  }
}

TEST(FsgpBgkMapperTest, APedestrianWalkingAcrossTheViewLeavesNoLastingObstacle) {
  // a 1.7 m tall pedestrian (radius 0.25 m) walks along y = 2 from x = -3 to 3 at 1 m/s in front
  // of a robot standing at the origin, its points fed to the mapper as if perception missed it
  FsgpBgkMapper dut(FsgpConfig{});
  const common::PointCloud ground = Surface([](double, double) { return 0.0; }, {0, 0});
  constexpr double kRadius_m = 0.25, kSpeed_m_s = 1.0, kFrame_s = 0.1, kY_m = 2.0;
  double worst_after_half_a_second = 0.0;
  for (int frame = 0; frame <= 80; ++frame) {
    const double t = frame * kFrame_s;
    const double x_p = -3.0 + kSpeed_m_s * t;  // past x = 3 the pedestrian is out of view
    std::vector<Eigen::Vector3f> points;
    for (Eigen::Index i = 0; i < ground.size(); ++i) {
      const Eigen::Vector3f p = ground.points.col(i);
      if (x_p <= 3.0 && std::hypot(p.x() - x_p, p.y() - kY_m) < kRadius_m) continue;
      points.emplace_back(p);
    }
    if (x_p <= 3.0) {
      for (double a = 0.0; a < 2.0 * M_PI; a += 0.2) {
        for (double z = 0.0; z <= 1.7; z += 0.05) {
          points.emplace_back(static_cast<float>(x_p + kRadius_m * std::cos(a)),
                              static_cast<float>(kY_m + kRadius_m * std::sin(a)),
                              static_cast<float>(z));
        }
      }
    }
    ASSERT_EQ(dut.Update(common::MakePointCloud(points), RobotAt(0, 0), t).status,
              MapUpdateStatus::kUpdated);
    if (x_p <= 3.0) {
      // where it stands is an obstacle
      EXPECT_GE(*dut.map().At(layers::kTraversability, {x_p, kY_m}), 0.8f) << "t = " << t;
    }
    // every cell of its path it left half a second ago or more is easy again
    for (double x = -3.0; x <= std::min(3.0, x_p - kRadius_m - 0.5 * kSpeed_m_s); x += 0.2) {
      worst_after_half_a_second =
          std::max(worst_after_half_a_second,
                   static_cast<double>(*dut.map().At(layers::kTraversability, {x, kY_m})));
    }
  }
  EXPECT_LT(worst_after_half_a_second, 0.5);
}

// Flat ground seen only beyond `blind_m` from the origin (as from a robot whose sensor cannot see
// the ground close round it) and not within 0.8 m of `hidden`, and a 1.7 m column of radius
// 0.25 m at each of `columns`.
common::PointCloud GroundAndColumns(double blind_m, const std::vector<Eigen::Vector2d>& columns,
                                    const Eigen::Vector2d& hidden = {100, 100}) {
  const common::PointCloud ground = Surface([](double, double) { return 0.0; }, {0, 0});
  std::vector<Eigen::Vector3f> points;
  for (Eigen::Index i = 0; i < ground.size(); ++i) {
    const Eigen::Vector3f p = ground.points.col(i);
    const bool under_column = std::any_of(columns.begin(), columns.end(), [&](const auto& c) {
      return std::hypot(p.x() - c.x(), p.y() - c.y()) < 0.25;
    });
    const bool seen = std::hypot(p.x(), p.y()) >= blind_m &&
                      std::hypot(p.x() - hidden.x(), p.y() - hidden.y()) >= 0.8;
    if (seen && !under_column) points.emplace_back(p);
  }
  for (const Eigen::Vector2d& c : columns) {
    for (double a = 0.0; a < 2.0 * M_PI; a += 0.2) {
      for (double z = 0.0; z <= 1.7; z += 0.05) {
        points.emplace_back(static_cast<float>(c.x() + 0.25 * std::cos(a)),
                            static_cast<float>(c.y() + 0.25 * std::sin(a)), static_cast<float>(z));
      }
    }
  }
  return common::MakePointCloud(points);
}

TEST(FsgpBgkMapperTest, AFaceInTheBlindZoneThatNoPointShowsAgainIsForgotten) {
  // a walker stands 1 m ahead of the robot, then leaves while the robot's sensor sees the ground
  // only beyond 2.6 m: its face in the blind zone (2.5 m) is forgotten once no point has shown it
  // for 2 s; a face 4 m away that no point shows either is kept
  FsgpBgkMapper dut(FsgpConfig{});
  const Eigen::Vector2d walker_W(1.1, 0.1), far_W(4.1, 0.1);  // cell centres
  ASSERT_EQ(dut.Update(GroundAndColumns(0.0, {walker_W, far_W}), RobotAt(0, 0), 0.0).status,
            MapUpdateStatus::kUpdated);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, walker_W), 1.0f);
  EXPECT_EQ(*dut.map().At(layers::kObstacleSeen, walker_W), 0.0f);
  const common::PointCloud blind = GroundAndColumns(2.6, {}, far_W);
  for (const double t : {0.5, 1.0, 1.5, 2.0}) {
    ASSERT_EQ(dut.Update(blind, RobotAt(0, 0), t).status, MapUpdateStatus::kUpdated);
    EXPECT_EQ(*dut.map().At(layers::kObstacle, walker_W), 1.0f) << "t = " << t;
    EXPECT_EQ(*dut.map().At(layers::kTraversability, walker_W), 1.0f) << "t = " << t;
  }
  ASSERT_EQ(dut.Update(blind, RobotAt(0, 0), 2.1).status, MapUpdateStatus::kUpdated);
  EXPECT_FALSE(dut.map().At(layers::kObstacle, walker_W).has_value());
  EXPECT_LT(*dut.map().At(layers::kTraversability, walker_W), 0.8f);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, far_W), 1.0f);
  EXPECT_EQ(*dut.map().At(layers::kTraversability, far_W), 1.0f);
}

TEST(FsgpBgkMapperTest, AFaceShownForLongerThanTheMemoryIsNotForgottenInTheBlindZone) {
  // a column 1 m ahead shows its face from 0 to 2 s (a wall seen on the way), then no point shows
  // it for 10 s (the robot turns beside it): it is the world's, not a walker's, and stays; one
  // shown from 0.5 to 2 s only is forgotten
  FsgpBgkMapper dut(FsgpConfig{});
  const Eigen::Vector2d wall_W(1.1, 0.1), walker_W(1.1, -0.9);  // cell centres
  for (const double t : {0.0, 0.5, 1.0, 1.5, 2.0}) {
    std::vector<Eigen::Vector2d> columns{wall_W};
    if (t >= 0.5) columns.push_back(walker_W);
    ASSERT_EQ(dut.Update(GroundAndColumns(0.0, columns), RobotAt(0, 0), t).status,
              MapUpdateStatus::kUpdated);
  }
  EXPECT_EQ(*dut.map().At(layers::kObstacleSince, wall_W), 0.0f);
  EXPECT_EQ(*dut.map().At(layers::kObstacleSince, walker_W), 0.5f);
  EXPECT_EQ(*dut.map().At(layers::kObstacleSeen, wall_W), 2.0f);
  ASSERT_EQ(dut.Update(GroundAndColumns(2.6, {}), RobotAt(0, 0), 12.0).status,
            MapUpdateStatus::kUpdated);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, wall_W), 1.0f);
  EXPECT_EQ(*dut.map().At(layers::kTraversability, wall_W), 1.0f);
  EXPECT_FALSE(dut.map().At(layers::kObstacle, walker_W).has_value());
}

TEST(FsgpBgkMapperTest, AWallsEndShownBrieflyStaysBesideTheWallWhileAWalkersTrailIsForgotten) {
  // a wall of two columns 1 m ahead shows its faces from 0 to 2 s; its end, a column beside them,
  // only at 1.5 and 2 s (seen along the wall from close by); a walker stands 1.3 m to the right at
  // 0.5 s and 1.9 m at 1 s (the ground where it stood first then hidden), apart from the wall. Then
  // no point shows any of them (the blind zone): the walker's trail is forgotten (its newest faces
  // at once, the older ones once those are), the wall's end stays with the wall
  FsgpBgkMapper dut(FsgpConfig{});
  const Eigen::Vector2d wall_W(1.1, 0.1), end_W(1.1, -0.3);  // cell centres
  const Eigen::Vector2d walker_first_W(1.1, -1.3), walker_then_W(1.1, -1.9);
  for (const double t : {0.0, 0.5, 1.0, 1.5, 2.0}) {
    std::vector<Eigen::Vector2d> columns{wall_W, {1.1, 0.5}};
    if (t >= 1.5) columns.push_back(end_W);
    if (t == 0.5) columns.push_back(walker_first_W);
    if (t == 1.0) columns.push_back(walker_then_W);
    const Eigen::Vector2d hidden = t >= 1.0 ? walker_first_W : Eigen::Vector2d(100, 100);
    ASSERT_EQ(dut.Update(GroundAndColumns(0.0, columns, hidden), RobotAt(0, 0), t).status,
              MapUpdateStatus::kUpdated);
  }
  EXPECT_EQ(*dut.map().At(layers::kObstacleSince, end_W), 1.5f);
  EXPECT_EQ(*dut.map().At(layers::kObstacleSeen, walker_first_W), 0.5f);
  EXPECT_EQ(*dut.map().At(layers::kObstacleSeen, walker_then_W), 1.0f);
  const common::PointCloud blind = GroundAndColumns(2.6, {});
  ASSERT_EQ(dut.Update(blind, RobotAt(0, 0), 3.05).status, MapUpdateStatus::kUpdated);
  EXPECT_FALSE(dut.map().At(layers::kObstacle, walker_then_W).has_value());
  for (const double t : {3.15, 12.0}) {
    ASSERT_EQ(dut.Update(blind, RobotAt(0, 0), t).status, MapUpdateStatus::kUpdated);
  }
  EXPECT_FALSE(dut.map().At(layers::kObstacle, walker_first_W).has_value());
  EXPECT_EQ(*dut.map().At(layers::kObstacle, end_W), 1.0f);
  EXPECT_EQ(*dut.map().At(layers::kTraversability, end_W), 1.0f);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, wall_W), 1.0f);
}

TEST(FsgpBgkMapperTest, AFaceShownForLongerThanTheMemoryClearsOnlyOnceSeenFreeForTheClearTime) {
  // a column 3 m ahead (beyond the blind zone) shows its face from 0 to 2 s, one 3 m to the side
  // from 1.5 to 2 s; then both are gone and the ground shows: the short-lived face clears at the
  // first free points, the lasting one once its cell has shown free for obstacle_clear (0.5 s),
  // and a face between starts that time again (the layers hold times in float, so the cell clears
  // at 3.3 s rather than 3.2 s: 3.2 - 2.7f is a little under 0.5)
  FsgpBgkMapper dut(FsgpConfig{});
  const Eigen::Vector2d wall_W(3.1, 0.1), walker_W(0.1, 3.1);  // cell centres
  for (const double t : {0.0, 0.5, 1.0, 1.5, 2.0}) {
    std::vector<Eigen::Vector2d> columns{wall_W};
    if (t >= 1.5) columns.push_back(walker_W);
    ASSERT_EQ(dut.Update(GroundAndColumns(0.0, columns), RobotAt(0, 0), t).status,
              MapUpdateStatus::kUpdated);
  }
  const common::PointCloud free = GroundAndColumns(0.0, {});
  ASSERT_EQ(dut.Update(free, RobotAt(0, 0), 2.1).status, MapUpdateStatus::kUpdated);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, walker_W), 0.0f);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, wall_W), 1.0f);
  EXPECT_EQ(*dut.map().At(layers::kFreeSince, wall_W), 2.1f);
  ASSERT_EQ(dut.Update(free, RobotAt(0, 0), 2.5).status, MapUpdateStatus::kUpdated);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, wall_W), 1.0f);
  ASSERT_EQ(dut.Update(GroundAndColumns(0.0, {wall_W}), RobotAt(0, 0), 2.6).status,
            MapUpdateStatus::kUpdated);
  EXPECT_FALSE(dut.map().At(layers::kFreeSince, wall_W).has_value());
  for (const double t : {2.7, 3.1}) {
    ASSERT_EQ(dut.Update(free, RobotAt(0, 0), t).status, MapUpdateStatus::kUpdated);
    EXPECT_EQ(*dut.map().At(layers::kObstacle, wall_W), 1.0f) << "t = " << t;
    EXPECT_EQ(*dut.map().At(layers::kTraversability, wall_W), 1.0f) << "t = " << t;
  }
  ASSERT_EQ(dut.Update(free, RobotAt(0, 0), 3.3).status, MapUpdateStatus::kUpdated);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, wall_W), 0.0f);
  EXPECT_LT(*dut.map().At(layers::kTraversability, wall_W), 0.8f);
}

TEST(FsgpBgkMapperTest, WithoutObstacleMemoryAFaceInTheBlindZoneStays) {
  FsgpConfig config;
  config.area.obstacle_memory_s = 0.0;
  FsgpBgkMapper dut(config);
  const Eigen::Vector2d walker_W(1.1, 0.1);
  for (const double t : {0.0, 0.5}) {
    ASSERT_EQ(dut.Update(GroundAndColumns(0.0, {walker_W}), RobotAt(0, 0), t).status,
              MapUpdateStatus::kUpdated);
  }
  ASSERT_EQ(dut.Update(GroundAndColumns(2.6, {}), RobotAt(0, 0), 10.0).status,
            MapUpdateStatus::kUpdated);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, walker_W), 1.0f);
  EXPECT_EQ(*dut.map().At(layers::kTraversability, walker_W), 1.0f);
  // and without a memory no face is lasting: the first free points clear it
  ASSERT_EQ(dut.Update(GroundAndColumns(0.0, {}), RobotAt(0, 0), 10.1).status,
            MapUpdateStatus::kUpdated);
  EXPECT_EQ(*dut.map().At(layers::kObstacle, walker_W), 0.0f);
}

// Flat ground with a 1.5 m high wall along y at x = 2 from y = -2 to 2, but for a gap of `gap` m
// centred on y = 0 where the LiDAR saw nothing at all (no wall and no ground).
common::PointCloud WallWithGap(double gap) {
  const common::PointCloud floor = Surface([](double, double) { return 0.0; }, {0, 0});
  std::vector<Eigen::Vector3f> points;
  for (Eigen::Index i = 0; i < floor.size(); ++i) {
    const Eigen::Vector3f p = floor.points.col(i);
    if (std::abs(p.x() - 2.0f) < 0.3f && std::abs(p.y()) < 0.5 * gap) continue;
    points.emplace_back(p);
  }
  for (double y = -2.0; y <= 2.0; y += 0.05) {
    if (std::abs(y) < 0.5 * gap) continue;
    for (double z = 0.0; z <= 1.5; z += 0.1) {
      points.emplace_back(2.0f, static_cast<float>(y), static_cast<float>(z));
    }
  }
  return common::MakePointCloud(points);
}

TEST(FsgpBgkMapperTest, AWallsUnseenCellsAreClosedButADoorwayStaysOpen) {
  FsgpBgkMapper closed(FsgpConfig{});
  ASSERT_EQ(closed.Update(WallWithGap(0.2), RobotAt(0, 0), 0.0).status, MapUpdateStatus::kUpdated);
  EXPECT_EQ(*closed.map().At(layers::kTraversability, {2.0, 0.0}), 1.0f);
  FsgpBgkMapper door(FsgpConfig{});
  ASSERT_EQ(door.Update(WallWithGap(1.0), RobotAt(0, 0), 0.0).status, MapUpdateStatus::kUpdated);
  EXPECT_LT(*door.map().At(layers::kTraversability, {2.0, 0.0}), 0.8f);
  EXPECT_EQ(*door.map().At(layers::kTraversability, {2.0, 1.0}), 1.0f);
}

TEST(FsgpBgkMapperTest, FlatGroundIsEasyEverywhere) {
  FsgpBgkMapper dut(FsgpConfig{});
  const MapUpdateResult result =
      dut.Update(Surface([](double, double) { return 0.0; }, {0, 0}), RobotAt(0, 0), 0.0);
  ASSERT_EQ(result.status, MapUpdateStatus::kUpdated);
  EXPECT_GT(result.observed_cells, 2000);
  EXPECT_LT(MeanNear(dut.map(), layers::kTraversability, {0, 0}, 4.0), 0.02);
  EXPECT_LT(MeanNear(dut.map(), layers::kSlope, {0, 0}, 4.0), 1.0 * kDegToRad);
  EXPECT_NEAR(MeanNear(dut.map(), layers::kElevation, {0, 0}, 4.0), 0.0, 0.005);
}

TEST(FsgpBgkMapperTest, PlanesAtTenAndTwentyDegreesGiveTheirSlope) {
  for (double degrees : {10.0, 20.0}) {
    const double gradient = std::tan(degrees * kDegToRad);
    FsgpBgkMapper dut(FsgpConfig{});
    ASSERT_EQ(dut.Update(Surface([=](double x, double) { return gradient * x; }, {0, 0}),
                         RobotAt(0, 0), 0.0)
                  .status,
              MapUpdateStatus::kUpdated);
    EXPECT_NEAR(MeanNear(dut.map(), layers::kSlope, {0, 0}, 3.0), degrees * kDegToRad,
                1.0 * kDegToRad)
        << degrees;
  }
}

TEST(FsgpBgkMapperTest, AStepRaisesTheCostAtItsEdgeOnly) {
  FsgpBgkMapper dut(FsgpConfig{});
  dut.Update(Surface([](double x, double) { return x > 2.05 ? 0.2 : 0.0; }, {0, 0}), RobotAt(0, 0),
             0.0);
  const double edge = MeanNear(dut.map(), layers::kTraversability, {2.05, 0}, 0.2);
  EXPECT_GT(edge, 0.3);
  // 1.5 m or more from the edge on either side the cost is low (a GP cannot follow a sharp step:
  // it leans into the cells next to it)
  for (double x : {-3.0, -2.0, -1.0, 3.6, 4.2}) {
    EXPECT_LT(MeanNear(dut.map(), layers::kTraversability, {x, 0}, 0.3), 0.1) << "x = " << x;
  }
}

TEST(FsgpBgkMapperTest, PcaDecorrelationKeepsTheSlope) {
  FsgpConfig config;
  config.pca = true;
  FsgpBgkMapper dut(config);
  const double gradient = std::tan(15.0 * kDegToRad);
  ASSERT_EQ(dut.Update(Surface([=](double x, double y) { return gradient * (0.6 * x + 0.8 * y); },
                               {0, 0}),
                       RobotAt(0, 0), 0.0)
                .status,
            MapUpdateStatus::kUpdated);
  EXPECT_NEAR(MeanNear(dut.map(), layers::kSlope, {0, 0}, 3.0), 15.0 * kDegToRad, 1.0 * kDegToRad);
}

TEST(FsgpBgkMapperTest, AccumulationFeedsTheLastFramesTogether) {
  FsgpConfig config;
  config.fuse = false;
  config.accumulate_frames = 3;
  FsgpBgkMapper dut(config);
  const common::PointCloud frame = Surface([](double, double) { return 0.0; }, {0, 0}, 2.0);
  int previous = 0;
  for (int k = 0; k < 4; ++k) {
    const MapUpdateResult result = dut.Update(frame, RobotAt(0, 0), k);
    // the window holds 1, 2, 3, then 3 frames' points
    EXPECT_EQ(result.window_points, std::min(k + 1, 3) * static_cast<int>(frame.size()));
    EXPECT_GE(result.window_points, previous);
    previous = result.window_points;
  }
}

TEST(FsgpBgkMapperTest, WithoutFusionTheLatestFrameDecides) {
  FsgpConfig config;
  config.fuse = false;
  config.smoothing_sigma_m = 0.0;
  FsgpBgkMapper dut(config);
  auto bump = [](double x, double y) {
    return 0.15 * std::exp(-((x - 2) * (x - 2) + y * y) / 0.1);
  };
  dut.Update(Surface(bump, {0, 0}), RobotAt(0, 0), 0.0);
  EXPECT_GT(*dut.map().At(layers::kTraversability, {2.0, 0.0}), 0.1);
  dut.Update(Surface([](double, double) { return 0.0; }, {0, 0}), RobotAt(0, 0), 1.0);
  EXPECT_LT(*dut.map().At(layers::kTraversability, {2.0, 0.0}), 0.02);
}

// Every layer of `a` equals `b`'s, cell for cell (NaN where the other is NaN); the count of known
// cells of the traversability layer.
int ExpectSameLayers(const common::GridLayers& a, const common::GridLayers& b) {
  EXPECT_EQ(a.LayerNames(), b.LayerNames());
  EXPECT_EQ(a.geometry().origin_W, b.geometry().origin_W);
  for (const std::string& name : a.LayerNames()) {
    const Eigen::MatrixXf& x = a.Layer(name);
    const Eigen::MatrixXf& y = b.Layer(name);
    const bool same = ((x.array() == y.array()) || (x.array().isNaN() && y.array().isNaN())).all();
    EXPECT_TRUE(same) << name;
  }
  return static_cast<int>((!a.Layer(layers::kTraversability).array().isNaN()).count());
}

// Bumps, a 1 m wall at y = 3 for 1 < x < 3 and a 0.2 m step up at x = 4 [m].
double BumpsAWallAndAStep(double x, double y) {
  const double step = x > 4.0 && std::abs(y) < 1.0 ? 0.2 : 0.0;
  const double wall = std::abs(y - 3.0) < 0.15 && x > 1.0 && x < 3.0 ? 1.0 : 0.0;
  return 0.1 * std::sin(1.3 * x) * std::cos(0.9 * y) + step + wall;
}

TEST(FsgpBgkMapperTest, AnUnfusedMapperOnAnotherMappersRegressionIsFsgpBitForBit) {
  // a robot driving over bumps past a wall and a low step, one frame empty: FSGP on FSGP-BGK's
  // regression against FSGP on its own, every layer after every frame
  FsgpConfig config;
  config.max_training_points = 150;
  FsgpBgkMapper bgk(config);
  const std::unique_ptr<FsgpBgkMapper> shared = FsgpBgkMapper::UnfusedOf(bgk);
  config.fuse = false;
  FsgpBgkMapper own(config);
  EXPECT_FALSE(shared->config().fuse);
  const auto terrain = BumpsAWallAndAStep;
  for (int frame = 0; frame < 8; ++frame) {
    const double x = 0.4 * frame;
    const common::PointCloud cloud =
        frame == 5 ? common::PointCloud{} : Surface(terrain, {x, 0.0}, 4.0, 0.01);
    const double t = 0.1 * frame;
    const MapUpdateResult reference = own.Update(cloud, RobotAt(x, 0.0), t);
    const MapUpdateResult regressed = bgk.Update(cloud, RobotAt(x, 0.0), t);
    const MapUpdateResult fused = shared->Update(cloud, RobotAt(x, 0.0), t);
    ASSERT_EQ(fused.status, reference.status) << "frame " << frame;
    EXPECT_EQ(fused.training_points, reference.training_points);
    EXPECT_EQ(fused.observed_cells, reference.observed_cells);
    // the regression's time, which the shared mapper did not spend, is reported as shared
    const StageTimes& times = regressed.times;
    EXPECT_EQ(fused.shared_wall_ms, times.crop + times.features + times.fit + times.predict);
    EXPECT_EQ(fused.times.crop + fused.times.features + fused.times.fit + fused.times.predict, 0.0);
    EXPECT_EQ(regressed.shared_cpu_ms, 0.0);
    if (fused.status == MapUpdateStatus::kUpdated) {
      EXPECT_GT(fused.shared_cpu_ms, 0.0);
    }
    const int known = ExpectSameLayers(shared->map(), own.map());
    EXPECT_GT(known, 0) << "frame " << frame;
  }
  // the wall and the step are obstacles in both
  EXPECT_EQ(*shared->map().At(layers::kTraversability, {2.0, 3.0}), 1.0f);
  EXPECT_EQ(*shared->map().At(layers::kTraversability, {4.0, 0.0}), 1.0f);
  // a frame the source has not seen is refused
  EXPECT_THROW(shared->Update(Surface(terrain, {0, 0}), RobotAt(0, 0), 5.0), std::logic_error);
}

TEST(FsgpBgkMapperTest, MappersOnAnotherMappersFeaturesAreTheirMethodsAtTheirMBitForBit) {
  // the ablation's mappers at M = 60 on FSGP-BGK's features at M = 150 (directly, and through the
  // FSGP fusing its regression), against each at M = 60 on its own, every layer after every frame;
  // a frame empty and one of too few points
  FsgpConfig config;
  config.max_training_points = 150;
  FsgpBgkMapper bgk(config);
  const std::unique_ptr<FsgpBgkMapper> fsgp = FsgpBgkMapper::UnfusedOf(bgk);
  const std::unique_ptr<FsgpBgkMapper> bgk_60 = FsgpBgkMapper::OnFeaturesOf(bgk, 60);
  const std::unique_ptr<FsgpBgkMapper> fsgp_60 = FsgpBgkMapper::OnFeaturesOf(*fsgp, 60);
  const std::unique_ptr<FsgpBgkMapper> unfused_60 = FsgpBgkMapper::UnfusedOf(*bgk_60);
  EXPECT_EQ(bgk_60->config().max_training_points, 60);
  EXPECT_TRUE(bgk_60->config().fuse);
  EXPECT_FALSE(fsgp_60->config().fuse);
  config.max_training_points = 60;
  FsgpBgkMapper own_bgk_60(config);
  config.fuse = false;
  FsgpBgkMapper own_fsgp_60(config);
  const auto terrain = BumpsAWallAndAStep;
  for (int frame = 0; frame < 8; ++frame) {
    const double x = 0.4 * frame;
    common::PointCloud cloud = Surface(terrain, {x, 0.0}, 4.0, 0.01);
    if (frame == 5) cloud = common::PointCloud{};
    if (frame == 6) cloud.points.conservativeResize(3, 5);
    const double t = 0.1 * frame;
    const Eigen::Isometry3d X_WB = RobotAt(x, 0.0);
    const MapUpdateResult source = bgk.Update(cloud, X_WB, t);
    fsgp->Update(cloud, X_WB, t);
    const MapUpdateResult sampled = bgk_60->Update(cloud, X_WB, t);
    const MapUpdateResult sampled_fsgp = fsgp_60->Update(cloud, X_WB, t);
    const MapUpdateResult unfused = unfused_60->Update(cloud, X_WB, t);
    const MapUpdateResult reference = own_bgk_60.Update(cloud, X_WB, t);
    const MapUpdateResult reference_fsgp = own_fsgp_60.Update(cloud, X_WB, t);
    ASSERT_EQ(reference_fsgp.status, reference.status) << "frame " << frame;
    ASSERT_EQ(sampled.status, reference.status) << "frame " << frame;
    ASSERT_EQ(sampled_fsgp.status, reference.status) << "frame " << frame;
    ASSERT_EQ(unfused.status, reference.status) << "frame " << frame;
    EXPECT_EQ(sampled.training_points, reference.training_points);
    EXPECT_EQ(sampled.window_points, reference.window_points);
    EXPECT_EQ(sampled.input_points, reference.input_points);
    if (reference.status == MapUpdateStatus::kUpdated) {
      EXPECT_EQ(sampled.training_points, 60) << "frame " << frame;
      // the crop's and the features' time, which the sampling mappers did not spend, is shared
      EXPECT_GT(sampled.shared_cpu_ms, 0.0);
      EXPECT_EQ(sampled_fsgp.shared_cpu_ms, sampled.shared_cpu_ms);
      EXPECT_GE(sampled.shared_wall_ms, source.times.crop);
      EXPECT_LE(sampled.shared_wall_ms, source.times.crop + source.times.features);
      EXPECT_EQ(sampled.times.crop, 0.0);
      // and FSGP on the sampling mapper's regression shares that regression and its features
      EXPECT_GT(unfused.shared_cpu_ms, sampled.shared_cpu_ms);
    }
    EXPECT_GT(ExpectSameLayers(bgk_60->map(), own_bgk_60.map()), 0) << "frame " << frame;
    EXPECT_GT(ExpectSameLayers(fsgp_60->map(), own_fsgp_60.map()), 0) << "frame " << frame;
    EXPECT_GT(ExpectSameLayers(unfused_60->map(), own_fsgp_60.map()), 0) << "frame " << frame;
  }
  // the step and the wall are obstacles; a frame the features' owner has not seen is refused
  EXPECT_EQ(*bgk_60->map().At(layers::kTraversability, {2.0, 3.0}), 1.0f);
  EXPECT_THROW(bgk_60->Update(Surface(terrain, {0, 0}), RobotAt(0, 0), 5.0), std::logic_error);
}

TEST(BgkUpdateTest, MatchesTheEquationsOnTwoFrames) {
  float m = std::numeric_limits<float>::quiet_NaN(), variance = 0.0f, t0 = 0.0f;
  BgkUpdate(0.6, 0.04, 10.0, 0.01, 0.1, 0.0, &m, &variance, &t0);
  EXPECT_FLOAT_EQ(m, 0.6f);
  EXPECT_FLOAT_EQ(variance, 0.04f);
  EXPECT_FLOAT_EQ(t0, 10.0f);
  EXPECT_NEAR(BgkUpdate(0.2, 0.09, 15.0, 0.01, 0.1, 0.0, &m, &variance, &t0), 1.0 / 0.14, 1e-6);
  // w_t = exp(-0.05), w_sigma = 1 / 0.14
  const double w_t = std::exp(-0.05);
  const double w_s = 1.0 / 0.14;
  EXPECT_NEAR(m, (w_t * w_s * 0.6 + 0.2) / (w_t * w_s + 1.0), 1e-6);
  EXPECT_NEAR(variance, (w_t * 0.04 + 0.09) / (w_t + 1.0), 1e-6);
  EXPECT_FLOAT_EQ(t0, 15.0f);
}

// The fixed-gain ablation ignores the variance: the same gain for a certain and an uncertain cell.
TEST(BgkUpdateTest, AFixedGainWeighsEveryCellAlike) {
  float certain_m = 0.8f, certain_v = 0.001f, certain_t = 5.0f;
  float vague_m = 0.8f, vague_v = 0.5f, vague_t = 5.0f;
  EXPECT_EQ(BgkUpdate(0.2, 0.01, 5.0, 0.01, 0.1, 4.0, &certain_m, &certain_v, &certain_t), 4.0);
  EXPECT_EQ(BgkUpdate(0.2, 0.01, 5.0, 0.01, 0.1, 4.0, &vague_m, &vague_v, &vague_t), 4.0);
  EXPECT_FLOAT_EQ(certain_m, (4.0f * 0.8f + 0.2f) / 5.0f);  // w_t = 1 at the same time
  EXPECT_FLOAT_EQ(vague_m, certain_m);
  // BGK would have weighed them 1 / 0.101 and 1 / 0.6
  float bgk_m = 0.8f, bgk_v = 0.5f, bgk_t = 5.0f;
  EXPECT_NEAR(BgkUpdate(0.2, 0.01, 5.0, 0.01, 0.1, 0.0, &bgk_m, &bgk_v, &bgk_t), 1.0 / 0.6, 1e-9);
}

// The relative weight takes the variance relative to a reference: GP variances far below eps
// (where the plain weight is 1 / eps for every cell) still weigh a certain cell above an uncertain
// one, 1 / eps at the reference.
TEST(BgkUpdateTest, TheRelativeWeightActsOnSmallVariances) {
  constexpr double kEps = 0.1, kReference = 0.002;
  float at_m = 0.8f, at_v = 0.002f, at_t = 5.0f;
  float certain_m = 0.8f, certain_v = 0.0005f, certain_t = 5.0f;
  float vague_m = 0.8f, vague_v = 0.006f, vague_t = 5.0f;
  EXPECT_NEAR(BgkUpdate(0.2, 0.002, 5.0, 0.01, kEps, 0.0, &at_m, &at_v, &at_t, kReference),
              1.0 / kEps, 1e-5);
  EXPECT_NEAR(
      BgkUpdate(0.2, 0.002, 5.0, 0.01, kEps, 0.0, &certain_m, &certain_v, &certain_t, kReference),
      2.0 / (kEps * (0.0005 / kReference + 1.0)), 1e-4);
  EXPECT_NEAR(BgkUpdate(0.2, 0.002, 5.0, 0.01, kEps, 0.0, &vague_m, &vague_v, &vague_t, kReference),
              2.0 / (kEps * (0.006 / kReference + 1.0)), 1e-4);
  // the certain cell keeps more of its 0.8, the uncertain one moves more toward the new 0.2
  EXPECT_GT(certain_m, at_m);
  EXPECT_LT(vague_m, at_m);
  // the plain weight barely tells them apart: 1 / 0.1005 against 1 / 0.106
  float plain_certain_m = 0.8f, plain_certain_v = 0.0005f, plain_certain_t = 5.0f;
  EXPECT_NEAR(BgkUpdate(0.2, 0.002, 5.0, 0.01, kEps, 0.0, &plain_certain_m, &plain_certain_v,
                        &plain_certain_t),
              1.0 / 0.1005, 1e-3);
}

// Relative to the new prediction's variance, a cell's old value counts the more, the less
// certain the new prediction is than it: twice as certain a cell weighs 2 / (eps (1/2 + 1)), half
// as certain 2 / (eps (2 + 1)); equal variances (zero too) weigh 1 / eps, the paper's weight for
// variances far below eps.
TEST(BgkUpdateTest, RelativeToThePredictionACellKeepsMoreOfItsValueAgainstAVaguerPrediction) {
  constexpr double kEps = 0.1;
  float vague_m = 0.8f, vague_v = 0.002f, vague_t = 5.0f;
  float sharp_m = 0.8f, sharp_v = 0.002f, sharp_t = 5.0f;
  float zero_m = 0.8f, zero_v = 0.0f, zero_t = 5.0f;
  const double w_vague = 2.0 / (kEps * 1.5), w_sharp = 2.0 / (kEps * 3.0);
  EXPECT_NEAR(BgkUpdate(0.2, 0.004, 5.0, 0.01, kEps, 0.0, &vague_m, &vague_v, &vague_t, 0.004),
              w_vague, 1e-5);
  EXPECT_NEAR(BgkUpdate(0.2, 0.001, 5.0, 0.01, kEps, 0.0, &sharp_m, &sharp_v, &sharp_t, 0.001),
              w_sharp, 1e-5);
  EXPECT_NEAR(BgkUpdate(0.2, 0.0, 5.0, 0.01, kEps, 0.0, &zero_m, &zero_v, &zero_t, 0.0), 1.0 / kEps,
              1e-9);
  EXPECT_NEAR(vague_m, (0.8 * w_vague + 0.2) / (w_vague + 1.0), 1e-6);
  EXPECT_NEAR(sharp_m, (0.8 * w_sharp + 0.2) / (w_sharp + 1.0), 1e-6);
  EXPECT_GT(vague_m, sharp_m);
  EXPECT_FLOAT_EQ(zero_m, (0.8f * 10.0f + 0.2f) / 11.0f);
}

// The mapper reports the weight its fusion used: the paper's uncertainty weight 1 / (sigma^2 +
// eps) with `variance_reference: none`, exactly the fixed gain when one is set; no weight on the
// first frame (nothing to fuse).
TEST(FsgpBgkMapperTest, ReportsTheFusionWeightAndTakesAFixedGain) {
  const auto ground = [](double x, double) { return 0.1 * x; };
  for (const double gain : {0.0, 4.0}) {
    FsgpConfig config;
    config.fixed_gain = gain;
    config.variance_reference = VarianceReference::kNone;
    FsgpBgkMapper dut(config);
    EXPECT_TRUE(
        std::isnan(dut.Update(Surface(ground, {0, 0}), RobotAt(0, 0), 0.0).mean_fusion_weight));
    const double weight =
        dut.Update(Surface(ground, {0, 0}), RobotAt(0, 0), 1.0).mean_fusion_weight;
    if (gain > 0.0) {
      EXPECT_EQ(weight, gain);
    } else {
      EXPECT_GT(weight, 1.0 / (1.0 + config.variance_epsilon));  // variance below 1
      EXPECT_LE(weight, 1.0 / config.variance_epsilon);
      EXPECT_NE(weight, 4.0);
    }
  }
  // the default, relative to the prediction: where a frame predicts as surely as the map holds,
  // the paper's 1 / eps (to the training subsets' difference); where it predicts less surely (a
  // smaller cloud: cells at its rim were inside the first), the map's value counts more
  FsgpBgkMapper relative{FsgpConfig{}};
  const double eps = FsgpConfig{}.variance_epsilon;
  relative.Update(Surface(ground, {0, 0}), RobotAt(0, 0), 0.0);
  EXPECT_NEAR(relative.Update(Surface(ground, {0, 0}), RobotAt(0, 0), 1.0).mean_fusion_weight,
              1.0 / eps, 0.01);
  EXPECT_GT(relative.Update(Surface(ground, {0, 0}, 2.0), RobotAt(0, 0), 2.0).mean_fusion_weight,
            1.05 / eps);  // 10.67; the paper's weight stays below 1 / eps
}

TEST(BgkUpdateTest, OldValuesDecayWithTime) {
  float recent_m = 0.8f, recent_v = 0.01f, recent_t = 99.0f;
  float old_m = 0.8f, old_v = 0.01f, old_t = 0.0f;
  BgkUpdate(0.0, 0.01, 100.0, 0.01, 0.1, 0.0, &recent_m, &recent_v, &recent_t);
  BgkUpdate(0.0, 0.01, 100.0, 0.01, 0.1, 0.0, &old_m, &old_v, &old_t);
  EXPECT_GT(recent_m, old_m);  // the one-second-old value weighs more than the 100-second-old one
  EXPECT_NEAR(old_m, 0.8 * std::exp(-1.0) / 0.11 / (std::exp(-1.0) / 0.11 + 1.0), 1e-6);
}

TEST(FsgpBgkMapperTest, CellsKeepTheirValuesWhileUnobservedAndStayAlignedWhenTheRobotMoves) {
  FsgpConfig config;
  config.area.map_size_m = 30.0;
  FsgpBgkMapper dut(config);
  // a bump at (3, 0) seen from the origin
  auto bump = [](double x, double y) {
    return 0.15 * std::exp(-((x - 3) * (x - 3) + y * y) / 0.1);
  };
  dut.Update(Surface(bump, {0, 0}), RobotAt(0, 0), 0.0);
  const float at_bump = *dut.map().At(layers::kTraversability, {3.0, 0.0});
  EXPECT_GT(at_bump, 0.2);
  // the robot moves 12 m away: the bump is out of every later window but its cell keeps its value
  dut.Update(Surface([](double, double) { return 0.0; }, {12, 0}), RobotAt(12, 0), 1.0);
  EXPECT_EQ(*dut.map().At(layers::kTraversability, {3.0, 0.0}), at_bump);
  EXPECT_EQ(*dut.map().At(layers::kLastObserved, {3.0, 0.0}), 0.0f);
  // 20 m away along y: the map has rolled; the world cell (3, 0) is gone, (12, 10) is known
  dut.Update(Surface([](double, double) { return 0.0; }, {12, 20}), RobotAt(12, 20), 2.0);
  EXPECT_FALSE(dut.map().At(layers::kTraversability, {3.0, 0.0}).has_value());
  EXPECT_TRUE(dut.map().At(layers::kTraversability, {12.0, 16.0}).has_value());
  EXPECT_EQ(*dut.map().At(layers::kLastObserved, {12.0, 22.0}), 2.0f);
}

TEST(FsgpBgkMapperTest, SeededRunsAreIdentical) {
  auto hills = [](double x, double y) { return 0.3 * std::sin(0.7 * x) * std::cos(0.5 * y); };
  FsgpConfig config;
  config.max_training_points = 200;  // forces the random sampling
  FsgpBgkMapper a(config), b(config);
  for (int frame = 0; frame < 3; ++frame) {
    a.Update(Surface(hills, {0.5 * frame, 0}), RobotAt(0.5 * frame, 0), 0.1 * frame);
    b.Update(Surface(hills, {0.5 * frame, 0}), RobotAt(0.5 * frame, 0), 0.1 * frame);
  }
  const Eigen::MatrixXf& ta = a.map().Layer(layers::kTraversability);
  const Eigen::MatrixXf& tb = b.map().Layer(layers::kTraversability);
  EXPECT_TRUE(((ta.array() == tb.array()) || (ta.array().isNaN() && tb.array().isNaN())).all());
}

TEST(FsgpBgkMapperTest, AHelperThreadGivesTheSameMapsBitForBit) {
  // the GP's mean on the helper while the updating thread computes the variance
  auto hills = [](double x, double y) { return 0.3 * std::sin(0.7 * x) * std::cos(0.5 * y); };
  FsgpBgkMapper one(FsgpConfig{}), two(FsgpConfig{});
  two.UseHelperThread();
  for (int frame = 0; frame < 4; ++frame) {
    one.Update(Surface(hills, {0.5 * frame, 0}), RobotAt(0.5 * frame, 0), 0.1 * frame);
    two.Update(Surface(hills, {0.5 * frame, 0}), RobotAt(0.5 * frame, 0), 0.1 * frame);
  }
  int known = 0;
  for (const std::string& name : one.map().LayerNames()) {
    const Eigen::ArrayXXf a = one.map().Layer(name).array();
    const Eigen::ArrayXXf b = two.map().Layer(name).array();
    EXPECT_TRUE(((a == b) || (a.isNaN() && b.isNaN())).all()) << name;
    if (name == layers::kTraversability) known = static_cast<int>((a == a).count());
  }
  EXPECT_GT(known, 1000);
}

TEST(FsgpBgkMapperTest, BadFramesLeaveTheMapUnchanged) {
  FsgpBgkMapper dut(FsgpConfig{});
  dut.Update(Surface([](double, double) { return 0.0; }, {0, 0}), RobotAt(0, 0), 0.0);
  const common::GridLayers before = dut.map();
  auto unchanged = [&] {
    const Eigen::MatrixXf& now = dut.map().Layer(layers::kTraversability);
    const Eigen::MatrixXf& then = before.Layer(layers::kTraversability);
    return ((now.array() == then.array()) || (now.array().isNaN() && then.array().isNaN())).all();
  };
  // empty
  EXPECT_EQ(dut.Update(common::PointCloud{}, RobotAt(0, 0), 1.0).status,
            MapUpdateStatus::kTooFewPoints);
  EXPECT_TRUE(unchanged());
  // three points
  common::PointCloud three = common::MakePointCloud({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  EXPECT_EQ(dut.Update(three, RobotAt(0, 0), 2.0).status, MapUpdateStatus::kTooFewPoints);
  EXPECT_TRUE(unchanged());
  // NaN and infinite points only
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  common::PointCloud invalid =
      common::MakePointCloud(std::vector<Eigen::Vector3f>(50, Eigen::Vector3f(nan, 0, inf)));
  const MapUpdateResult result = dut.Update(invalid, RobotAt(0, 0), 3.0);
  EXPECT_EQ(result.status, MapUpdateStatus::kTooFewPoints);
  EXPECT_EQ(result.dropped_invalid, 50);
  EXPECT_TRUE(unchanged());
}

}  // namespace
}  // namespace trav::mapping
