#include "sim/lidar/scan_pattern.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"

namespace trav::lidar {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr int kFrame = 20000;
constexpr double kRadToDeg = 180.0 / M_PI;

// 1 x 1 deg cells over azimuth [0, 360) x elevation [-7, 52) hit by frames [0, frames).
std::set<int> CoveredCells(const ScanPattern& pattern, int frames) {
  std::set<int> cells;
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(frames) * kFrame; ++i) {
    const Eigen::Vector3f d = pattern.Ray(i).direction_L;
    double azimuth = Azimuth(d) * kRadToDeg;
    if (azimuth < 0) azimuth += 360.0;
    const int row = static_cast<int>(std::floor(Elevation(d) * kRadToDeg + 7.0));
    if (row < 0 || row >= 59) continue;
    cells.insert(row * 360 + static_cast<int>(azimuth) % 360);
  }
  return cells;
}

TEST(Mid360PatternTest, ElevationsStayWithinTheFieldOfView) {
  const Mid360Pattern dut;
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

TEST(Mid360PatternTest, AzimuthIsEvenOverAFrame) {
  const Mid360Pattern dut;
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

TEST(Mid360PatternTest, LinesComeInGroupsOfFour) {
  const Mid360Pattern dut;
  for (int i = 0; i < 16; ++i) EXPECT_EQ(dut.Ray(i).line, i % 4);
  // the four beams of a group lie within 4 deg of each other
  for (std::int64_t group = 0; group < 5000; group += 97) {
    const Eigen::Vector3f first = dut.Ray(4 * group).direction_L;
    const Eigen::Vector3f last = dut.Ray(4 * group + 3).direction_L;
    EXPECT_LT(std::acos(std::min(1.0f, first.dot(last))) * kRadToDeg, 4.0);
    EXPECT_GT(std::acos(std::min(1.0f, first.dot(last))) * kRadToDeg, 3.0);
  }
}

TEST(Mid360PatternTest, SuccessiveFramesFillEachOthersGaps) {
  const Mid360Pattern dut;
  std::size_t previous = 0;
  for (int frames : {1, 2, 5, 10}) {
    const std::size_t covered = CoveredCells(dut, frames).size();
    EXPECT_GT(covered, previous) << frames << " frames";
    previous = covered;
  }
  // one frame covers part of the 21,240 cells; ten frames nearly all of them
  EXPECT_LT(CoveredCells(dut, 1).size(), 0.8 * 21240);
  EXPECT_GT(previous, 0.9 * 21240);
}

TEST(Mid360PatternTest, BatchRaysEqualSingleRays) {
  const Mid360Pattern dut;
  Eigen::Matrix3Xf directions(3, 37);
  Eigen::VectorXi lines(37);
  dut.Rays(1001, 37, &directions, &lines);
  for (int k = 0; k < 37; ++k) {
    EXPECT_EQ(directions.col(k), dut.Ray(1001 + k).direction_L);
    EXPECT_EQ(lines[k], dut.Ray(1001 + k).line);
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
  // row 5 is row 0 again; lines count rays in groups of four
  EXPECT_EQ(dut->Ray(5).direction_L, dut->Ray(0).direction_L);
  EXPECT_EQ(dut->Ray(5).line, 1);
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
