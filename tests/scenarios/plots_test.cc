#include "scenarios/run/plots.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input_error.h"
#include "tests/test_environment.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::ThrowsMessage;

constexpr char kHeader[] =
    "t,x,y,yaw,v_forward,yaw_rate,roll_deg,pitch_deg,vertical_acceleration,cmd_v,cmd_omega,"
    "goal_distance,mapping_error";
constexpr char kComputeHeader[] =
    ",lidar_ms,mapping_ms,planning_ms,control_ms,physics_ms,render_ms";

// A fresh folder under the system's temporary folder, removed at the end of the test.
class PlotsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("trav_plots_test_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // 4 s of a synthetic run at 10 Hz: the mapping error is NaN until the first map (t < 1 s).
  void WriteTimeseries(bool with_compute) const {
    std::ofstream file(dir_ / "timeseries.csv");
    file << kHeader << (with_compute ? kComputeHeader : "") << '\n';
    for (int i = 1; i <= 40; ++i) {
      const double t = 0.1 * i;
      char line[512];
      std::snprintf(line, sizeof(line), "%.3f,%.4f,0,0,%.4f,0,%.3f,%.3f,0,%.3f,0,%.4f,", t, t,
                    std::min(1.0, 0.5 * t), 3.0 * std::sin(t), 2.0 * std::cos(t), 1.0, 10.0 - t);
      file << line << (t < 1.0 ? std::string("nan") : std::to_string(0.2 / t));
      if (with_compute) file << ",1.2,6.5,3.1,2.4,4.0,0.000";
      file << '\n';
    }
  }

  std::vector<std::string> Files() const {
    std::vector<std::string> names;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir_)) {
      names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  fs::path dir_;
};

struct PngSize {
  std::uint32_t width{0};
  std::uint32_t height{0};
};

// The size from a PNG's IHDR chunk; fails the test if `path` does not start as a PNG file.
::testing::AssertionResult ReadPngSize(const fs::path& path, PngSize* size) {
  std::ifstream file(path, std::ios::binary);
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(file)),
                                         std::istreambuf_iterator<char>());
  if (bytes.size() < 33) {
    return ::testing::AssertionFailure() << path << " has " << bytes.size() << " bytes";
  }
  constexpr std::array<unsigned char, 8> kSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (!std::equal(kSignature.begin(), kSignature.end(), bytes.begin())) {
    return ::testing::AssertionFailure() << path << " lacks the PNG signature";
  }
  // chunk length 13, type IHDR, then width and height, big-endian
  const auto big_endian = [&](std::size_t at) {
    return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
           (std::uint32_t{bytes[at + 2]} << 8) | std::uint32_t{bytes[at + 3]};
  };
  if (big_endian(8) != 13 || std::string(bytes.begin() + 12, bytes.begin() + 16) != "IHDR") {
    return ::testing::AssertionFailure() << path << " does not start with an IHDR chunk";
  }
  size->width = big_endian(16);
  size->height = big_endian(20);
  return ::testing::AssertionSuccess();
}

#define SKIP_WITHOUT_GNUPLOT()                                                                   \
  if (!ProgramAvailable("gnuplot")) {                                                            \
    TRAV_SKIP_UNLESS_CI("gnuplot is not installed (scripts/install-deps installs gnuplot-nox)"); \
  }

TEST_F(PlotsTest, WritesEveryPlotAsPngAndSvgOfTheAskedSize) {
  SKIP_WITHOUT_GNUPLOT();
  WriteTimeseries(/*with_compute=*/true);
  PlotOptions options;
  options.width = 640;
  options.height = 360;
  const PlotResult result = WriteRunPlots(dir_.string(), options);

  EXPECT_EQ(result.status, PlotStatus::kWritten) << result.message;
  EXPECT_THAT(result.written,
              ElementsAre("speed.png", "roll_pitch.png", "mapping_error.png", "compute.png"));
  EXPECT_THAT(result.message, IsEmpty());
  for (const std::string& name : result.written) {
    PngSize size;
    ASSERT_TRUE(ReadPngSize(dir_ / name, &size));
    EXPECT_EQ(size.width, 640u) << name;
    EXPECT_EQ(size.height, 360u) << name;
    std::ifstream svg(dir_ / SvgName(name));
    const std::string text((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
    EXPECT_THAT(text, HasSubstr("<svg")) << SvgName(name);
    EXPECT_THAT(text, HasSubstr("width=\"640\" height=\"360\"")) << SvgName(name);
  }
  // no script, log or partial image left behind
  EXPECT_THAT(Files(), ElementsAre("compute.png", "compute.svg", "mapping_error.png",
                                   "mapping_error.svg", "roll_pitch.png", "roll_pitch.svg",
                                   "speed.png", "speed.svg", "timeseries.csv"));
  EXPECT_EQ(PlotsJson(result),
            nlohmann::json({"speed.png", "roll_pitch.png", "mapping_error.png", "compute.png"}));
}

// A series with an interval gets a translucent band of its colour behind its curve, in the
// legend under its own title; a band column missing is a reason, not a crash.
TEST_F(PlotsTest, IntervalsAreDrawnAsBandsBehindTheirCurves) {
  SKIP_WITHOUT_GNUPLOT();
  std::ofstream(dir_ / "rates.csv") << "value,rate,low,high\n1,0.5,0.3,0.7\n2,0.8,0.6,0.9\n"
                                       "3,0.9,0.75,0.97\n";
  const LinePlot banded{"rates.png", "Rates",
                        "value",     "value",
                        "rate",      {{"rate", "success rate", "low", "high", "95 % interval"}}};
  LinePlot missing = banded;
  missing.file = "missing.png";
  missing.series[0].band_high = "upper";
  const PlotResult result =
      WriteLinePlots((dir_ / "rates.csv").string(), {banded, missing}, dir_.string());
  EXPECT_EQ(result.status, PlotStatus::kWritten) << result.message;
  EXPECT_THAT(result.written, ElementsAre("rates.png"));
  EXPECT_THAT(result.message, HasSubstr("missing.png: no column upper"));
  std::ifstream svg(dir_ / "rates.svg");
  const std::string text((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
  EXPECT_THAT(text, HasSubstr("95 % interval"));
  EXPECT_THAT(text, HasSubstr("success rate"));
  // the band: a filled path in the series' colour (the palette's first), 20 % opaque
  EXPECT_THAT(text, HasSubstr("fill = 'rgb(  0, 114, 178)'"));
  EXPECT_THAT(text, HasSubstr("fill-opacity = '0.20"));
}

// A first frame's set-up (one row 100 times the others) does not flatten a plot: its range ends
// just above the 99th percentile; without such a spike, or with too few rows, nothing is clipped.
TEST(RobustUpperLimitTest, ClipsASpikeAndNothingElse) {
  std::vector<double> values(200, 1.0);
  for (int i = 0; i < 200; i += 10) values[static_cast<std::size_t>(i)] = 2.0;
  EXPECT_FALSE(RobustUpperLimit(values).has_value());  // 2 is the 99th percentile: no spike
  values[0] = 100.0;
  values.push_back(std::numeric_limits<double>::quiet_NaN());
  const std::optional<double> top = RobustUpperLimit(values);
  ASSERT_TRUE(top.has_value());
  EXPECT_DOUBLE_EQ(*top, 2.4);  // 1.2 x the 99th percentile (2)
  EXPECT_FALSE(RobustUpperLimit({100.0, 1.0, 1.0}).has_value());
}

TEST_F(PlotsTest, WithoutComputeColumnsWritesNoComputePlot) {
  SKIP_WITHOUT_GNUPLOT();
  WriteTimeseries(/*with_compute=*/false);
  const PlotResult result = WriteRunPlots(dir_.string());

  EXPECT_EQ(result.status, PlotStatus::kWritten) << result.message;
  EXPECT_THAT(result.written, ElementsAre("speed.png", "roll_pitch.png", "mapping_error.png"));
  EXPECT_THAT(result.message, HasSubstr("compute.png: no compute columns"));
  EXPECT_FALSE(fs::exists(dir_ / "compute.png"));
  PngSize size;
  ASSERT_TRUE(ReadPngSize(dir_ / "speed.png", &size));
  EXPECT_EQ(size.width, 800u);
  EXPECT_EQ(size.height, 480u);
}

TEST_F(PlotsTest, MappingErrorOfOnlyNaNWritesNoMappingPlot) {
  SKIP_WITHOUT_GNUPLOT();
  std::ofstream(dir_ / "timeseries.csv") << kHeader << "\n"
                                         << "0.1,0,0,0,0.5,0,1,2,0,0.5,0,9,nan\n"
                                         << "0.2,0,0,0,0.6,0,1,2,0,0.6,0,9,nan\n"
                                         << "0.3,0,0,0,0.7";  // truncated last line
  const PlotResult result = WriteRunPlots(dir_.string());

  EXPECT_EQ(result.status, PlotStatus::kWritten) << result.message;
  EXPECT_THAT(result.written, ElementsAre("speed.png", "roll_pitch.png"));
  EXPECT_THAT(result.message, HasSubstr("mapping_error.png: no row with values"));
  EXPECT_FALSE(fs::exists(dir_ / "mapping_error.png"));
}

TEST_F(PlotsTest, MissingGnuplotIsReportedNotThrown) {
  WriteTimeseries(/*with_compute=*/true);
  PlotOptions options;
  options.gnuplot = "trav-no-such-gnuplot";
  const PlotResult result = WriteRunPlots(dir_.string(), options);

  EXPECT_EQ(result.status, PlotStatus::kNoGnuplot);
  EXPECT_THAT(result.written, IsEmpty());
  EXPECT_THAT(result.message, HasSubstr("gnuplot is not installed"));
  EXPECT_TRUE(PlotsJson(result).is_null());
  EXPECT_THAT(Files(), ElementsAre("timeseries.csv"));
}

TEST_F(PlotsTest, MissingTimeseriesIsReported) {
  const PlotResult result = WriteRunPlots(dir_.string());

  EXPECT_EQ(result.status, PlotStatus::kNoTimeseries);
  EXPECT_THAT(result.message, HasSubstr("timeseries.csv does not exist"));
  EXPECT_TRUE(PlotsJson(result).is_null());
}

TEST_F(PlotsTest, FailingGnuplotLeavesNoImages) {
  WriteTimeseries(/*with_compute=*/true);
  PlotOptions options;
  options.gnuplot = "false";  // exits 1 without writing anything
  const PlotResult result = WriteRunPlots(dir_.string(), options);

  EXPECT_EQ(result.status, PlotStatus::kGnuplotFailed);
  EXPECT_THAT(result.message, HasSubstr("failed (exit status 1)"));
  EXPECT_THAT(Files(), ElementsAre("timeseries.csv"));
}

TEST_F(PlotsTest, BadSizeThrows) {
  PlotOptions options;
  options.width = 10;
  EXPECT_THAT([&] { (void)WriteRunPlots(dir_.string(), options); },
              ThrowsMessage<common::InputError>(HasSubstr("plots.width")));
}

}  // namespace
}  // namespace trav::scenarios
