#include "sim/lidar/scan_pattern.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"
#include "sim/lidar/scan_pattern_statistics.h"

namespace trav::lidar {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr int kFrame = 20000;
constexpr double kRadToDeg = 180.0 / M_PI;

// 1 x 1 deg cells of the field hit by frames [0, frames).
int CoveredCells(const ScanPattern& pattern, int frames) {
  return ComputePatternStatistics(pattern, 0, static_cast<std::int64_t>(frames) * kFrame)
      .covered_cells;
}

TEST(ProceduralMid360PatternTest, ElevationsStayWithinTheFieldOfView) {
  const ProceduralMid360Pattern dut;
  float lowest = 90.0f, highest = -90.0f;
  for (std::int64_t i = 0; i < 3 * kFrame; ++i) {
    const float elevation = Elevation(dut.Ray(i).direction_L) * static_cast<float>(kRadToDeg);
    lowest = std::min(lowest, elevation);
    highest = std::max(highest, elevation);
    ASSERT_NEAR(dut.Ray(i).direction_L.norm(), 1.0f, 1e-6f);
  }
  EXPECT_GE(lowest, -7.0f);
  EXPECT_LE(highest, 52.0f);
  // the sweep reaches both ends of the field in every frame
  EXPECT_LT(lowest, -5.0f);
  EXPECT_GT(highest, 49.0f);
}

TEST(ProceduralMid360PatternTest, AzimuthIsEvenOverAFrame) {
  const ProceduralMid360Pattern dut;
  int counts[12] = {};
  for (std::int64_t i = 0; i < kFrame; ++i) {
    double azimuth = Azimuth(dut.Ray(i).direction_L) * kRadToDeg;
    if (azimuth < 0) azimuth += 360.0;
    ++counts[static_cast<int>(azimuth / 30.0) % 12];
  }
  double chi_square = 0.0;
  const double expected = kFrame / 12.0;
  for (int count : counts) chi_square += (count - expected) * (count - expected) / expected;
  // 11 degrees of freedom: 31.26 is the 0.1 % critical value
  EXPECT_LT(chi_square, 31.26);
}

TEST(ProceduralMid360PatternTest, LinesComeInGroupsOfFour) {
  const ProceduralMid360Pattern dut;
  for (int i = 0; i < 16; ++i) EXPECT_EQ(dut.Ray(i).line, i % 4);
  // the four beams of a group lie within 4 deg of each other
  for (std::int64_t group = 0; group < 5000; group += 97) {
    const Eigen::Vector3f first = dut.Ray(4 * group).direction_L;
    const Eigen::Vector3f last = dut.Ray(4 * group + 3).direction_L;
    EXPECT_LT(std::acos(std::min(1.0f, first.dot(last))) * kRadToDeg, 4.0);
    EXPECT_GT(std::acos(std::min(1.0f, first.dot(last))) * kRadToDeg, 3.0);
  }
}

TEST(ProceduralMid360PatternTest, SuccessiveFramesFillEachOthersGaps) {
  const ProceduralMid360Pattern dut;
  int previous = 0;
  for (int frames : {1, 2, 5, 10}) {
    const int covered = CoveredCells(dut, frames);
    EXPECT_GT(covered, previous) << frames << " frames";
    previous = covered;
  }
  // one frame covers part of the 21,240 cells; ten frames nearly all of them
  EXPECT_LT(CoveredCells(dut, 1), 0.8 * 21240);
  EXPECT_GT(previous, 0.9 * 21240);
}

TEST(ProceduralMid360PatternTest, BatchRaysEqualSingleRays) {
  const ProceduralMid360Pattern dut;
  Eigen::Matrix3Xf directions(3, 37);
  Eigen::VectorXi lines(37);
  dut.Rays(1001, 37, &directions, &lines);
  for (int k = 0; k < 37; ++k) {
    EXPECT_EQ(directions.col(k), dut.Ray(1001 + k).direction_L);
    EXPECT_EQ(lines[k], dut.Ray(1001 + k).line);
  }
}

// The shipped table read from its file, independent of the copy compiled into the library.
std::unique_ptr<TablePattern> ShippedTableFile() { return TablePattern::Load(TRAV_MID360_TABLE); }

TEST(ShippedMid360TableTest, FirstPassIsTheFileRowForRow) {
  const auto file = ShippedTableFile();
  const auto dut = TablePattern::Mid360();
  ASSERT_EQ(dut->size(), 50157);
  ASSERT_EQ(dut->period(), 2 * kFrame);
  for (std::int64_t i = 0; i < dut->period(); ++i) {
    ASSERT_EQ(dut->Ray(i).direction_L, file->Ray(i).direction_L) << "row " << i;
    ASSERT_EQ(dut->Ray(i).line, i % 4);
  }
  // the second pass goes on where the table goes on: it begins at row 40,000's azimuth
  EXPECT_NEAR(dut->azimuth_turn_per_pass_rad() * kRadToDeg, 95.306 - 268.99, 1e-3);
  EXPECT_NEAR(Azimuth(dut->Ray(dut->period()).direction_L),
              Azimuth(file->Ray(dut->period()).direction_L), 1e-5);
  EXPECT_EQ(dut->Ray(dut->period()).direction_L.z(), file->Ray(0).direction_L.z());
}

TEST(ShippedMid360TableTest, LaterFramesHaveTheStatisticsOfTheTablesFrames) {
  const auto file = ShippedTableFile();
  const auto dut = TablePattern::Mid360();
  // frames 2, 3 (the second pass) and 5, 6 (across the boundary of the third and fourth passes)
  // against the table's frames: one frame against the same rows, two frames against both
  for (const std::int64_t first_frame : {2, 5}) {
    SCOPED_TRACE(first_frame);
    for (const int frames : {1, 2}) {
      const std::int64_t table_first = frames == 1 ? (first_frame % 2) * kFrame : 0;
      const PatternStatistics table = ComputePatternStatistics(*file, table_first, frames * kFrame);
      const PatternStatistics later =
          ComputePatternStatistics(*dut, first_frame * kFrame, frames * kFrame);
      // a pass turns about z only: the elevation histogram is the table's, exactly
      EXPECT_EQ(later.elevation_share, table.elevation_share);
      // azimuth shares per 30 deg band within 0.01; coverage of the field within 4 % (two frames
      // of different passes are turned against each other by other angles than the table's two)
      for (int k = 0; k < PatternStatistics::kAzimuthBands; ++k)
        EXPECT_NEAR(later.azimuth_share[k], table.azimuth_share[k], 0.01) << "band " << k;
      EXPECT_NEAR(later.coverage, table.coverage, 0.04 * table.coverage);
    }
  }
}

TEST(ShippedMid360TableTest, CoverageKeepsGrowingBeyondTheTable) {
  const auto dut = TablePattern::Mid360();
  int previous = 0;
  for (const int frames : {1, 2, 4, 8}) {
    const int covered = CoveredCells(*dut, frames);
    EXPECT_GT(covered, previous) << frames << " frames";
    previous = covered;
  }
  EXPECT_GT(previous, 0.95 * 21240);
}

TEST(ShippedMid360TableTest, BatchRaysEqualSingleRaysAcrossAPassBoundary) {
  const auto dut = TablePattern::Mid360();
  Eigen::Matrix3Xf directions(3, 37);
  Eigen::VectorXi lines(37);
  dut->Rays(3 * dut->period() - 17, 37, &directions, &lines);
  for (int k = 0; k < 37; ++k) {
    EXPECT_EQ(directions.col(k), dut->Ray(3 * dut->period() - 17 + k).direction_L);
    EXPECT_EQ(lines[k], dut->Ray(3 * dut->period() - 17 + k).line);
  }
}

class TablePatternTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& text) {
    path_ = (std::filesystem::temp_directory_path() /
             ("trav_scan_table_" + std::to_string(getpid()) + ".csv"))
                .string();
    std::ofstream(path_) << text;
    return path_;
  }
  void TearDown() override { std::filesystem::remove(path_); }
  std::string path_;
};

TEST_F(TablePatternTest, ReadsASmallTableExactlyAndWraps) {
  const auto dut =
      TablePattern::Load(Write("Time/s,Azimuth/deg,Zenith/deg\n"
                               "1,0,90\n2,90,90\n3,180,45\n4,270,0\n5,45,180\n"));
  ASSERT_EQ(dut->size(), 5);
  EXPECT_TRUE(dut->Ray(0).direction_L.isApprox(Eigen::Vector3f(1, 0, 0)));
  EXPECT_TRUE(dut->Ray(1).direction_L.isApprox(Eigen::Vector3f(0, 1, 0), 1e-6f));
  EXPECT_TRUE(dut->Ray(2).direction_L.isApprox(
      Eigen::Vector3f(-std::sqrt(0.5f), 0, std::sqrt(0.5f)), 1e-6f));
  EXPECT_TRUE(dut->Ray(3).direction_L.isApprox(Eigen::Vector3f(0, 0, 1), 1e-6f));
  EXPECT_NEAR(dut->Ray(4).direction_L.z(), -1.0f, 1e-6f);
  // a loaded table wraps unturned: ray 5 is row 0 again, with row 0's line (lines count rows in
  // groups of four)
  EXPECT_EQ(dut->period(), 5);
  EXPECT_EQ(dut->azimuth_turn_per_pass_rad(), 0.0);
  EXPECT_EQ(dut->Ray(5).direction_L, dut->Ray(0).direction_L);
  EXPECT_EQ(dut->Ray(5).line, 0);
  EXPECT_EQ(dut->Ray(8).line, 3);
}

TEST_F(TablePatternTest, MalformedTablesAreInputErrorsNamingFileAndLine) {
  EXPECT_THAT([&] { TablePattern::Load(Write("Azimuth,Zenith\n1,2\n")); },
              ThrowsMessage<common::InputError>(HasSubstr("line 1: expected the header")));
  EXPECT_THAT([&] { TablePattern::Load(Write("Time/s,Azimuth/deg,Zenith/deg\n1,0,90\n2,x,90\n")); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("line 3: expected 'index,azimuth_deg,zenith_deg'")));
  EXPECT_THAT([&] { TablePattern::Load(Write("Time/s,Azimuth/deg,Zenith/deg\n1,0,200\n")); },
              ThrowsMessage<common::InputError>(HasSubstr("line 2")));
  EXPECT_THAT([&] { TablePattern::Load(Write("Time/s,Azimuth/deg,Zenith/deg\n")); },
              ThrowsMessage<common::InputError>(HasSubstr("the scan table has no rows")));
  EXPECT_THAT([] { TablePattern::Load("/nonexistent/mid360.csv"); },
              ThrowsMessage<common::InputError>(
                  HasSubstr("/nonexistent/mid360.csv: cannot open scan table")));
}

}  // namespace
}  // namespace trav::lidar
