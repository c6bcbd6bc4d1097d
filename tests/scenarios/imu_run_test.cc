// The IMU in a run: gravity at rest and the yaw rate of a calibrated turn in imu.csv.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/yaml_reader.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;

// The rows of a CSV file with a header line, as numbers.
std::vector<std::vector<double>> ReadRows(const fs::path& path) {
  std::ifstream file(path);
  std::string line;
  std::getline(file, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(file, line)) {
    std::vector<double> row;
    std::stringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) row.push_back(std::stod(field));
    rows.push_back(row);
  }
  return rows;
}

// Mean of column `column` over the rows with t (column 0) in [from_s, to_s].
double Mean(const std::vector<std::vector<double>>& rows, int column, double from_s, double to_s) {
  double sum = 0.0;
  int n = 0;
  for (const std::vector<double>& row : rows) {
    if (row[0] < from_s || row[0] > to_s) continue;
    sum += row[static_cast<std::size_t>(column)];
    ++n;
  }
  return sum / n;
}

TEST(ImuRunTest, MeasuresGravityAtRestAndTheYawRateOfACalibratedTurn) {
  // standing for 1 s, then turning in place at 1 rad/s with the calibrated skid-steer mapping
  const Scenario scenario = LoadScenario(common::YamlDocument::Parse(R"(
schema_version: 1
terrain: {type: flat, size: [12, 12]}
duration: 4
drive:
  - {v: 0, omega: 0, duration: 1}
  - {v: 0, omega: 1.0, duration: 3}
lidar: {enabled: false}
video: {enabled: false}
)",
                                                                     "imu_run.yaml"));
  const fs::path out = fs::temp_directory_path() / ("trav_imu_" + std::to_string(getpid()));
  fs::remove_all(out);
  fs::create_directories(out);
  RunScenario(scenario, RobotModelPath(scenario, TRAV_MODELS_DIR), out.string());
  const std::vector<std::vector<double>> imu = ReadRows(out / "imu.csv");
  const std::vector<std::vector<double>> trajectory = ReadRows(out / "trajectory.csv");
  fs::remove_all(out);

  // 200 Hz from t = 0: 800 samples in 4 s (the last physics step starts at 3.998 s)
  ASSERT_EQ(imu.size(), 800u);
  for (std::size_t k = 0; k < imu.size(); ++k) ASSERT_NEAR(imu[k][0], 0.005 * k, 1e-9);
  // at rest (after the drop onto the ground has settled): +g along the IMU's z, no rotation;
  // the mean of 100 samples of noise 0.014 m/s^2 is within 0.005 m/s^2
  EXPECT_NEAR(Mean(imu, 3, 0.5, 1.0), 9.81, 0.02);
  EXPECT_NEAR(Mean(imu, 1, 0.5, 1.0), 0.0, 0.01);
  EXPECT_NEAR(Mean(imu, 6, 0.5, 1.0), 0.0, 0.002);
  // turning: the gyroscope's yaw rate is the robot's (trajectory.csv column yaw_rate) and the
  // commanded 1 rad/s within the calibration's 5 %
  const double gyro_z = Mean(imu, 6, 2.0, 3.9);
  EXPECT_NEAR(gyro_z, Mean(trajectory, 8, 2.0, 3.9), 0.01);
  EXPECT_NEAR(gyro_z, 1.0, 0.05);
  // the measured values differ from the true ones by the noise only
  EXPECT_NEAR(Mean(imu, 6, 2.0, 3.9), Mean(imu, 12, 2.0, 3.9), 0.002);
}

}  // namespace
}  // namespace trav::scenarios
