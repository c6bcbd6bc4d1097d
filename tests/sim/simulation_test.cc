#include "sim/simulation.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include "controller/skid_steer.h"

namespace trav::sim {
namespace {

const std::string kRobotModel = std::string(TRAV_MODELS_DIR) + "/scout_mini.xml";

WorldOptions Options() {
  WorldOptions options;
  options.robot_model_path = kRobotModel;
  return options;
}

TerrainWorld FlatWorld() {
  TerrainConfig config;
  config.type = TerrainType::kFlat;
  config.size_m = {30, 30};
  return GenerateTerrain(config);
}

void StepFor(Simulation* sim, double seconds) {
  const int steps = static_cast<int>(std::lround(seconds / sim->timestep()));
  for (int i = 0; i < steps; ++i) ASSERT_EQ(sim->Step(), StepStatus::kOk);
}

void Drive(Simulation* sim, const common::Twist2& command) {
  sim->SetWheelSpeedCommands(controller::ToWheelSpeeds(command, controller::SkidSteerConfig{}));
}

double Yaw(const Simulation& sim) { return common::ToRollPitchYaw(sim.State().X_WB.linear()).yaw; }

TEST(RobotModelTest, LoadsOnItsOwnWithTheSpecifiedMassAndGeometry) {
  char error[1000] = "";
  mjModel* model = mj_loadXML(kRobotModel.c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(model, nullptr) << error;
  EXPECT_NEAR(mj_getTotalmass(model), 23.0, 1e-9);
  EXPECT_EQ(model->nu, 4);
  EXPECT_EQ(model->opt.integrator, mjINT_IMPLICIT);
  EXPECT_EQ(model->opt.cone, mjCONE_ELLIPTIC);
  // wheel collision shapes are ellipsoids (cylinders bounce in MuJoCo 2.2.2)
  const int wheel = mj_name2id(model, mjOBJ_GEOM, "front_left_wheel");
  ASSERT_GE(wheel, 0);
  EXPECT_EQ(model->geom_type[wheel], mjGEOM_ELLIPSOID);
  EXPECT_DOUBLE_EQ(model->geom_size[3 * wheel], 0.0875);
  mj_deleteModel(model);
}

TEST(SimulationTest, AtRestOnFlatGroundTheRobotSettlesAndStays) {
  Simulation dut(FlatWorld(), common::Pose2{}, Options());
  StepFor(&dut, 2.0);
  const Eigen::Vector3d settled = dut.State().X_WB.translation();
  StepFor(&dut, 10.0);
  const Eigen::Vector3d later = dut.State().X_WB.translation();
  EXPECT_LT((later - settled).norm(), 1e-3);
  EXPECT_EQ(dut.warning_count(), 0) << (dut.warnings().empty() ? "" : dut.warnings().front());
  // ground clearance: chassis bottom 0.0275 m above B, spec 0.115 m above ground (suspension sag
  // and contact softness within 1 cm)
  EXPECT_NEAR(settled.z() + 0.0275, 0.115, 0.01);
  // the MID-360 sits on the top plate, its optical centre 0.292 m above the ground
  EXPECT_NEAR(dut.LidarPose().translation().z() - settled.z() + 0.0875, 0.292, 0.01);
}

TEST(SimulationTest, DrivesStraightAtOneMeterPerSecond) {
  Simulation dut(FlatWorld(), common::Pose2{}, Options());
  StepFor(&dut, 1.0);
  const Eigen::Vector3d start = dut.State().X_WB.translation();
  Drive(&dut, {1.0, 0.0});
  StepFor(&dut, 5.0);
  const Eigen::Vector3d end = dut.State().X_WB.translation();
  EXPECT_NEAR(end.x() - start.x(), 5.0, 0.25);
  EXPECT_NEAR(end.y() - start.y(), 0.0, 0.05);
}

TEST(SimulationTest, TurnsInPlaceAtTheCommandedRateWithTheCalibratedMapping) {
  Simulation dut(FlatWorld(), common::Pose2{}, Options());
  StepFor(&dut, 1.0);
  Drive(&dut, {0.0, 1.0});
  StepFor(&dut, 1.0);  // spin up
  double turned = 0.0;
  double previous = Yaw(dut);
  const int steps = static_cast<int>(std::lround(3.0 / dut.timestep()));
  for (int i = 0; i < steps; ++i) {
    ASSERT_EQ(dut.Step(), StepStatus::kOk);
    turned += common::WrapAngle(Yaw(dut) - previous);
    previous = Yaw(dut);
  }
  EXPECT_NEAR(turned / 3.0, 1.0, 0.1);
}

TEST(SimulationTest, ClimbsATwentyDegreeSlope) {
  TerrainConfig config;
  config.type = TerrainType::kSlope;
  config.size_m = {30, 10};
  config.slope.angle_deg = 20.0;
  config.slope.start_x_m = -10.0;
  common::Pose2 start;
  start.position = Eigen::Vector2d(-13.0, 0.0);
  Simulation dut(GenerateTerrain(config), start, Options());
  Drive(&dut, {1.0, 0.0});
  StepFor(&dut, 10.0);
  const Eigen::Vector3d p = dut.State().X_WB.translation();
  // well up the ramp: at least 5 m along it, 1.7 m higher than the start
  EXPECT_GT(p.x(), -10.0 + 5.0 * std::cos(20.0 * M_PI / 180.0));
  EXPECT_GT(p.z(), 1.7);
  EXPECT_NEAR(common::ToRollPitchYaw(dut.State().X_WB.linear()).pitch, -20.0 * M_PI / 180.0, 0.05);
}

// Drives at 1 m/s for 8 s towards a step at x = 0 and returns the final state.
common::RobotState DriveAtStep(double step_height_m) {
  TerrainConfig config;
  config.type = TerrainType::kStep;
  config.size_m = {20, 10};
  config.step.height_m = step_height_m;
  config.step.x_m = 0.0;
  common::Pose2 start;
  start.position = Eigen::Vector2d(-3.0, 0.0);
  Simulation sim(GenerateTerrain(config), start, Options());
  Drive(&sim, {1.0, 0.0});
  StepFor(&sim, 8.0);
  return sim.State();
}

TEST(SimulationTest, CannotClimbATwentyCentimetreStep) {
  const common::RobotState state = DriveAtStep(0.2);
  // the front wheels get onto the step, the rear axle stays below it: stuck, nose up
  const Eigen::Vector3d rear_axle_W = state.X_WB * Eigen::Vector3d(-0.2255, 0.0, 0.0);
  EXPECT_LT(rear_axle_W.x(), 0.0);
  EXPECT_LT(state.X_WB.translation().x(), 0.5);
}

TEST(SimulationTest, ClimbsAFiveCentimetreStep) {
  const common::RobotState state = DriveAtStep(0.05);
  EXPECT_GT(state.X_WB.translation().x(), 3.0);
  EXPECT_NEAR(state.X_WB.translation().z(), 0.05 + 0.09, 0.01);
}

TEST(SimulationTest, HeightFieldRowsRunAlongY) {
  // a ramp rising along +x: at (6, -3) the ground is 4 tan(20 deg) high; were rows and columns
  // swapped, the robot would rest at the height of x = -3 (the flat part)
  TerrainConfig config;
  config.type = TerrainType::kSlope;
  config.size_m = {20, 16};
  config.slope.start_x_m = 2.0;
  common::Pose2 start;
  start.position = Eigen::Vector2d(6.0, -3.0);
  start.yaw = M_PI / 2;  // across the slope, so it does not roll away
  Simulation dut(GenerateTerrain(config), start, Options());
  StepFor(&dut, 1.0);
  const double ground = 4.0 * std::tan(20.0 * M_PI / 180.0);
  EXPECT_NEAR(dut.State().X_WB.translation().z(), ground + 0.0875, 0.05);
}

TEST(SimulationTest, SeededRunsAreBitIdentical) {
  TerrainConfig config;
  config.type = TerrainType::kHilly;
  config.size_m = {20, 20};
  auto run = [&] {
    Simulation sim(GenerateTerrain(config), common::Pose2{}, Options());
    Drive(&sim, {1.2, 0.4});
    for (int i = 0; i < 1000; ++i) sim.Step();
    return sim.State();
  };
  const common::RobotState a = run();
  const common::RobotState b = run();
  EXPECT_TRUE((a.X_WB.matrix().array() == b.X_WB.matrix().array()).all());
  EXPECT_TRUE((a.v_WB_B.array() == b.v_WB_B.array()).all());
}

TEST(SimulationTest, MissingRobotModelIsAnInputError) {
  WorldOptions options = Options();
  options.robot_model_path = "/nonexistent/robot.xml";
  EXPECT_THROW(Simulation(FlatWorld(), common::Pose2{}, options), std::runtime_error);
}

}  // namespace
}  // namespace trav::sim
