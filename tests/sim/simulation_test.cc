#include "sim/simulation.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include "common/input_error.h"
#include "controller/skid_steer.h"
#include "mapping/physical_truth.h"

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

// The shipped URDF is what `trav urdf` writes from the MJCF today (regenerate it with
// `trav urdf --out models/scout_mini.urdf --overwrite` after changing the MJCF).
TEST(RobotModelTest, TheShippedUrdfIsGeneratedFromTheMjcf) {
  std::ifstream file(std::string(TRAV_MODELS_DIR) + "/scout_mini.urdf");
  const std::string shipped{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  EXPECT_EQ(shipped, RobotUrdf(kRobotModel));
}

// MuJoCo reads URDF too: the URDF's robot has the MJCF's masses, wheels and joints. (MuJoCo makes
// the URDF's root link, base_link, its world body: the base's frame is the world's, and its mass
// is in the text.)
TEST(RobotModelTest, TheUrdfLoadsWithTheMjcfsMassWheelsAndJoints) {
  const std::string urdf_path =
      ::testing::TempDir() + "/scout_mini_" + std::to_string(getpid()) + ".urdf";
  const std::string text = RobotUrdf(kRobotModel);
  std::ofstream(urdf_path) << text;
  char error[1000] = "";
  mjModel* urdf = mj_loadXML(urdf_path.c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(urdf, nullptr) << error;
  mjModel* mjcf = mj_loadXML(kRobotModel.c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(mjcf, nullptr) << error;
  const int base = mj_name2id(mjcf, mjOBJ_BODY, "base");
  EXPECT_NE(text.find("<link name=\"base_link\">\n    <inertial>\n      <origin xyz=\"0.00174725 0 "
                      "0.0938832\" rpy=\"0 -1.5641 3.14159\"/>\n      <mass value=\"18.2\"/>"),
            std::string::npos);
  EXPECT_NEAR(mjcf->body_mass[base], 18.2, 1e-9);
  EXPECT_NEAR(mj_getTotalmass(urdf), mj_getTotalmass(mjcf) - mjcf->body_mass[base], 1e-9);
  mjData* urdf_data = mj_makeData(urdf);
  mjData* mjcf_data = mj_makeData(mjcf);
  mj_forward(urdf, urdf_data);
  mj_forward(mjcf, mjcf_data);
  for (const char* wheel :
       {"front_left_wheel", "rear_left_wheel", "front_right_wheel", "rear_right_wheel"}) {
    const int u = mj_name2id(urdf, mjOBJ_BODY, wheel);
    const int j = mj_name2id(urdf, mjOBJ_JOINT, wheel);
    const int c = mj_name2id(mjcf, mjOBJ_BODY, wheel);
    ASSERT_GE(u, 0) << wheel;
    ASSERT_GE(j, 0) << wheel;
    EXPECT_EQ(urdf->jnt_type[j], mjJNT_HINGE) << wheel;
    EXPECT_NEAR(urdf->body_mass[u], mjcf->body_mass[c], 1e-9) << wheel;
    // the wheel's centre in the base frame (the MJCF's base starts level, 0.0875 m up)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(urdf_data->xpos[3 * u + k],
                  mjcf_data->xpos[3 * c + k] - mjcf_data->xpos[3 * base + k], 1e-9)
          << wheel;
    }
    // the wheel rolls about its y axis: a cylinder of the tyre's radius and width
    const int geom = urdf->body_geomadr[u];
    EXPECT_EQ(urdf->geom_type[geom], mjGEOM_CYLINDER);
    EXPECT_NEAR(urdf->geom_size[3 * geom], 0.0875, 1e-9);
    EXPECT_NEAR(urdf->geom_size[3 * geom + 1], 0.04, 1e-9);
  }
  // the suspensions are prismatic
  EXPECT_EQ(urdf->jnt_type[mj_name2id(urdf, mjOBJ_JOINT, "front_left_suspension")], mjJNT_SLIDE);
  mj_deleteData(urdf_data);
  mj_deleteData(mjcf_data);
  mj_deleteModel(urdf);
  mj_deleteModel(mjcf);
  std::remove(urdf_path.c_str());
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

// A 30 x 10 m world that rises at `angle_deg` along x from x = -10 m.
TerrainWorld SlopeWorld(double angle_deg) {
  TerrainConfig config;
  config.type = TerrainType::kSlope;
  config.size_m = {30, 10};
  config.slope.angle_deg = angle_deg;
  config.slope.start_x_m = -10.0;
  return GenerateTerrain(config);
}

TEST(SimulationTest, ClimbsATwentyDegreeSlope) {
  common::Pose2 start;
  start.position = Eigen::Vector2d(-13.0, 0.0);
  Simulation dut(SlopeWorld(20.0), start, Options());
  Drive(&dut, {1.0, 0.0});
  StepFor(&dut, 10.0);
  const Eigen::Vector3d p = dut.State().X_WB.translation();
  // well up the ramp: at least 5 m along it, 1.7 m higher than the start
  EXPECT_GT(p.x(), -10.0 + 5.0 * std::cos(20.0 * M_PI / 180.0));
  EXPECT_GT(p.z(), 1.7);
  EXPECT_NEAR(common::ToRollPitchYaw(dut.State().X_WB.linear()).pitch, -20.0 * M_PI / 180.0, 0.05);
}

// A 20 x 10 m world with a step of `step_height_m` at x = 0 (higher for x > 0).
TerrainWorld StepWorld(double step_height_m) {
  TerrainConfig config;
  config.type = TerrainType::kStep;
  config.size_m = {20, 10};
  config.step.height_m = step_height_m;
  config.step.x_m = 0.0;
  return GenerateTerrain(config);
}

// Drives at `speed_m_s` (1 m/s) toward a step at x = 0 from x = -3 for 8 s and returns the final
// state; the largest pitch on the way (before x = 6) in `max_pitch_rad` if given.
common::RobotState DriveAtStep(double step_height_m, double speed_m_s = 1.0,
                               double* max_pitch_rad = nullptr) {
  common::Pose2 start;
  start.position = Eigen::Vector2d(-3.0, 0.0);
  Simulation sim(StepWorld(step_height_m), start, Options());
  Drive(&sim, {speed_m_s, 0.0});
  double pitch = 0.0;
  for (int i = 0; i < static_cast<int>(8.0 / sim.timestep()); ++i) {
    EXPECT_EQ(sim.Step(), StepStatus::kOk);
    const common::RobotState state = sim.State();
    if (state.X_WB.translation().x() < 6.0) {
      pitch = std::max(pitch, std::abs(common::ToRollPitchYaw(state.X_WB.linear()).pitch));
    }
  }
  if (max_pitch_rad != nullptr) *max_pitch_rad = pitch;
  return sim.State();
}

TEST(SimulationTest, CannotClimbATwentyCentimetreStep) {
  const common::RobotState state = DriveAtStep(0.2);
  // the front wheels get onto the step, the rear axle stays below it: stuck, nose up
  const Eigen::Vector3d rear_axle_W = state.X_WB * Eigen::Vector3d(-0.2255, 0.0, 0.0);
  EXPECT_LT(rear_axle_W.x(), 0.0);
  EXPECT_LT(state.X_WB.translation().x(), 0.5);
}

// The step limits docs/navigation.md gives (measured by sweeping heights in 1 cm and speeds): at
// 1 m/s the robot climbs 0.16 m and not 0.17 m; at 1.5 m/s it rears on a 0.10 m step (43 deg
// of pitch, against 21 deg at 1 m/s).
TEST(SimulationTest, ClimbsSixteenCentimetresAtOneMetrePerSecondButNotSeventeen) {
  EXPECT_GT(DriveAtStep(0.16).X_WB.translation().x(), 3.0);
  EXPECT_LT(DriveAtStep(0.17).X_WB.translation().x(), 0.5);
}

// Drives at 1 m/s onto a step at x = 0 from 1.5 m before it (up) or off it from 1.5 m behind its
// edge (down) for 6 s: the largest tilt from upright [deg], and how far past the edge the front and
// rear axles got [m].
struct StepPass {
  double max_tilt_deg{0.0};
  double front_past_m{-1e9};
  double rear_past_m{0.0};
};
StepPass PassStep(double step_height_m, bool up) {
  common::Pose2 start;
  start.position = Eigen::Vector2d(up ? -1.5 : 1.5, 0.0);
  start.yaw = up ? 0.0 : M_PI;
  Simulation sim(StepWorld(step_height_m), start, Options());
  Drive(&sim, {1.0, 0.0});
  const double sign = up ? 1.0 : -1.0;
  StepPass pass;
  for (int i = 0; i < static_cast<int>(6.0 / sim.timestep()); ++i) {
    sim.Step();
    const Eigen::Isometry3d X_WB = sim.State().X_WB;
    pass.max_tilt_deg = std::max(
        pass.max_tilt_deg, std::acos(std::clamp(X_WB.linear()(2, 2), -1.0, 1.0)) * 180 / M_PI);
    pass.front_past_m =
        std::max(pass.front_past_m, sign * (X_WB * Eigen::Vector3d(0.2255, 0, 0)).x());
    pass.rear_past_m = sign * (X_WB * Eigen::Vector3d(-0.2255, 0, 0)).x();
  }
  return pass;
}

// The physical ground truth's step limits (docs/ground-truth.md): pushed by the rear wheels the
// front wheels get onto 0.22 m (the rear ones stay below) and the robot rears over at 0.25 m;
// driving off a step tilts it less than 45 deg from 0.26 m, 45 deg from 0.27 m (the limit) and
// more from 0.28 m.
TEST(SimulationTest, TheFrontWheelsGetOntoTwentyTwoCentimetresAndTheRobotRearsOverAtTwentyFive) {
  const StepPass onto = PassStep(0.22, true);
  EXPECT_GT(onto.front_past_m, 0.1);
  EXPECT_LT(onto.rear_past_m, 0.0);
  EXPECT_LT(onto.max_tilt_deg, 45.0);
  EXPECT_GT(PassStep(0.25, true).max_tilt_deg, 90.0);
}

TEST(SimulationTest, DrivingOffTwentySevenCentimetresTiltsItAboutFortyFiveDegrees) {
  const StepPass low = PassStep(0.26, false);
  EXPECT_GT(low.rear_past_m, 1.0);
  EXPECT_LT(low.max_tilt_deg, 45.0);
  EXPECT_NEAR(PassStep(0.27, false).max_tilt_deg, 45.0, 0.5);
  EXPECT_GT(PassStep(0.28, false).max_tilt_deg, 45.0);
}

TEST(SimulationTest, RearsOnATenCentimetreStepAtFullSpeed) {
  double slow_pitch = 0.0, fast_pitch = 0.0;
  EXPECT_GT(DriveAtStep(0.10, 1.0, &slow_pitch).X_WB.translation().x(), 3.0);
  DriveAtStep(0.10, 1.5, &fast_pitch);
  EXPECT_LT(slow_pitch, 25.0 * M_PI / 180.0);
  EXPECT_GT(fast_pitch, 35.0 * M_PI / 180.0);
}

// Drives at 1 m/s toward a step of `step_height_m` at x = 0 from x = -1.5 m and, from when its
// nose is up by 5 deg, at `climb` (the navigator's climb hold: planner/navigation/navigator.h);
// returns how far past the edge the rear axle got in 6 s [m].
double RearPastAfterClimbing(double step_height_m, const common::Twist2& climb) {
  common::Pose2 start;
  start.position = Eigen::Vector2d(-1.5, 0.0);
  Simulation sim(StepWorld(step_height_m), start, Options());
  for (int i = 0; i < static_cast<int>(6.0 / sim.timestep()); ++i) {
    const double nose_up = -common::ToRollPitchYaw(sim.State().X_WB.linear()).pitch;
    Drive(&sim, nose_up > 5.0 * M_PI / 180.0 ? climb : common::Twist2{1.0, 0.0});
    sim.Step();
  }
  return (sim.State().X_WB * Eigen::Vector3d(-0.2255, 0, 0)).x();
}

// docs/navigation.md, "Climbing a step": driven straight at 1.1 m/s from when the front wheels
// climb, the robot gets onto 0.14 m; turning at 0.3 rad/s either way (one side at 0.92 m/s), or
// straight at 0.8 m/s, its rear wheels stall against the face.
TEST(SimulationTest, ClimbsFourteenCentimetresDrivenStraightButNotWhileTurning) {
  EXPECT_GT(RearPastAfterClimbing(0.14, {1.1, 0.0}), 3.0);
  for (const common::Twist2& stalls :
       {common::Twist2{1.1, 0.3}, common::Twist2{1.1, -0.3}, common::Twist2{0.8, 0.0}}) {
    EXPECT_LT(RearPastAfterClimbing(0.14, stalls), 0.0) << stalls.v << " " << stalls.omega;
  }
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

// The world a run leaves beside its outputs: world.xml and terrain.bin load in MuJoCo on their own
// (as `simulate world.xml` does) into the model the simulation built in memory: the same height
// field samples, sizes and geoms.
TEST(WorldExportTest, TheExportedWorldLoadsAsTheSimulatedOne) {
  TerrainConfig config;
  config.type = TerrainType::kRuin;
  config.size_m = {14, 10};
  const TerrainWorld world = GenerateTerrain(config);
  const Simulation simulated(world, common::Pose2{}, Options());
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("trav_world_export_" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  ExportWorld(world, Options(), {}, folder.string());
  char error[1000] = "";
  mjModel* loaded = mj_loadXML((folder / "world.xml").c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(loaded, nullptr) << error;
  const mjModel& memory = *simulated.model();
  const int hfield = mj_name2id(loaded, mjOBJ_HFIELD, "terrain");
  ASSERT_EQ(hfield, mj_name2id(&memory, mjOBJ_HFIELD, "terrain"));
  EXPECT_EQ(loaded->hfield_nrow[hfield], world.geometry.num_y);
  EXPECT_EQ(loaded->hfield_ncol[hfield], world.geometry.num_x);
  for (int k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(loaded->hfield_size[4 * hfield + k], memory.hfield_size[4 * hfield + k]);
  }
  const int samples = loaded->hfield_nrow[hfield] * loaded->hfield_ncol[hfield];
  double worst = 0.0;
  for (int i = 0; i < samples; ++i) {
    worst = std::max(
        worst, std::abs(static_cast<double>(loaded->hfield_data[loaded->hfield_adr[hfield] + i] -
                                            memory.hfield_data[memory.hfield_adr[hfield] + i])));
  }
  // MuJoCo renormalises a file's samples to [0, 1]: at most a float's rounding apart
  EXPECT_LT(worst, 1e-6);
  EXPECT_EQ(loaded->ngeom, memory.ngeom);
  EXPECT_EQ(loaded->nbody, memory.nbody);
  mj_deleteModel(loaded);
  std::filesystem::remove_all(folder);
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

TerrainWorld SmallFlatWorld() {
  TerrainConfig config;
  config.type = TerrainType::kFlat;
  config.size_m = {8, 8};
  return GenerateTerrain(config);
}

// A box mover 0.4 m long, `width_m` wide and 0.6 m tall crossing from `start_W` at `velocity_W`.
MovingObstacle Crate(const Eigen::Vector2d& start_W, const Eigen::Vector2d& velocity_W,
                     double width_m = 0.4) {
  MovingObstacle crate;
  crate.name = "crate";
  crate.shape = MoverShape::kBox;
  crate.box_half_extents_m = {0.2, 0.5 * width_m};
  crate.half_height_m = 0.3;
  crate.motion = ConstantVelocityMotion{start_W, velocity_W, 0.0};
  return crate;
}

// A static box obstacle on flat ground, `height_m` tall, across the robot's path at x = x_m.
Obstacle Barrier(const std::string& name, double x_m, double height_m) {
  Obstacle barrier;
  barrier.name = name;
  barrier.shape = ShapeType::kBox;
  barrier.size = Eigen::Vector3d(0.1, 1.0, 0.5 * height_m);
  barrier.X_WO.translation() = Eigen::Vector3d(x_m, 0.0, 0.5 * height_m);
  return barrier;
}

TEST(RobotModelTest, TheFootprintHoldsTheWheelsAndIsThePlannersDefault) {
  const Simulation sim(SmallFlatWorld(), common::Pose2{}, Options());
  const common::Footprint& footprint = sim.RobotFootprint();
  // wheel centres 0.2255 m ahead and behind, radius 0.0875; 0.245 m to the side, half-width 0.04
  EXPECT_NEAR(footprint.half_length_m, 0.2255 + 0.0875, 2e-3);
  EXPECT_NEAR(footprint.half_width_m, 0.245 + 0.04, 2e-3);
  // the planners' default is this robot's footprint, so that they cannot drift apart
  EXPECT_NEAR(common::Footprint{}.half_length_m, footprint.half_length_m, 2e-3);
  EXPECT_NEAR(common::Footprint{}.half_width_m, footprint.half_width_m, 2e-3);
}

TEST(RobotModelTest, ThePhysicalTruthsRestingBodyIsTheModelsWheelsAndChassis) {
  char error[1000] = "";
  mjModel* model = mj_loadXML(kRobotModel.c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(model, nullptr) << error;
  mjData* data = mj_makeData(model);
  mj_forward(model, data);
  const mapping::RestingBody body;
  const int base = mj_name2id(model, mjOBJ_BODY, "base");
  const int wheel = mj_name2id(model, mjOBJ_GEOM, "front_left_wheel");
  const int chassis = mj_name2id(model, mjOBJ_GEOM, "chassis");
  ASSERT_GE(base, 0);
  ASSERT_GE(wheel, 0);
  ASSERT_GE(chassis, 0);
  // the wheel centre in the base frame (the base is unrotated in the model's pose)
  for (int axis = 0; axis < 2; ++axis) {
    const double offset = data->geom_xpos[3 * wheel + axis] - data->xpos[3 * base + axis];
    EXPECT_NEAR(std::abs(offset), axis == 0 ? body.wheel_x_m : body.wheel_y_m, 1e-9);
  }
  EXPECT_DOUBLE_EQ(model->geom_size[3 * wheel], body.wheel_radius_m);
  EXPECT_DOUBLE_EQ(model->geom_size[3 * wheel + 1], body.wheel_half_width_m);
  EXPECT_DOUBLE_EQ(model->geom_size[3 * chassis], body.chassis_half_length_m);
  EXPECT_DOUBLE_EQ(model->geom_size[3 * chassis + 1], body.chassis_half_width_m);
  // the belly's height above the wheels' lowest points: the truth's clearance
  const double belly_above_base =
      model->geom_pos[3 * chassis + 2] - model->geom_size[3 * chassis + 2];
  EXPECT_NEAR(belly_above_base + body.wheel_radius_m, mapping::GroundTruthConfig{}.clearance_m,
              1e-9);
  mj_deleteData(data);
  mj_deleteModel(model);
}

TEST(SimulationContactTest, ARestingRobotTouchesTheGroundWithItsFourWheelsOnly) {
  Simulation dut(SmallFlatWorld(), common::Pose2{}, Options());
  StepFor(&dut, 1.0);
  std::vector<RobotContact> contacts;
  dut.RobotContacts(&contacts);
  ASSERT_FALSE(contacts.empty());
  std::set<int> wheels;
  for (const RobotContact& contact : contacts) {
    EXPECT_EQ(contact.part, RobotPart::kWheel);
    EXPECT_EQ(contact.target, ContactTarget::kTerrain);
    EXPECT_EQ(contact.target_name, "ground");
    EXPECT_FALSE(IsCollision(contact));
    EXPECT_GT(contact.normal_W.z(), 0.99);  // from the ground up into the wheel
    wheels.insert(contact.wheel);
  }
  EXPECT_EQ(wheels, (std::set<int>{0, 1, 2, 3}));
  // the wheels carry the robot's weight (23 kg)
  double load_N = 0.0;
  for (const RobotContact& contact : contacts) load_N += contact.normal_force_N;
  EXPECT_NEAR(load_N, 23.0 * 9.81, 0.5);
}

// The first contact between the resting robot and a crate `width_m` wide that comes head-on at
// 1 m/s from x = 1.5 m, and the time it happened after the crate started [s].
struct CrateHit {
  RobotContact contact;     // its target_name dangles once the simulation is gone:
  std::string target_name;  // a copy
  double time_s{0.0};
};
CrateHit HitByCrate(double width_m) {
  const std::vector<MovingObstacle> movers = {Crate({1.5, 0.0}, {-1.0, 0.0}, width_m)};
  Simulation sim(SmallFlatWorld(), common::Pose2{}, Options(), movers);
  EXPECT_EQ(sim.num_movers(), 1);
  StepFor(&sim, 0.5);  // settle (the crate has not moved: poses are set by the caller)
  const double t0 = sim.time();
  std::vector<RobotContact> contacts;
  while (sim.time() < t0 + 2.0) {
    sim.SetMoverPoses(sim.time() - t0);
    EXPECT_EQ(sim.Step(), StepStatus::kOk);
    sim.RobotContacts(&contacts);
    for (const RobotContact& contact : contacts) {
      if (contact.target != ContactTarget::kMover) continue;
      // the crate passes through the ground: MuJoCo has no crate-ground contact
      const int crate = mj_name2id(sim.model(), mjOBJ_GEOM, "mover_crate");
      const int ground = mj_name2id(sim.model(), mjOBJ_GEOM, "ground");
      for (int i = 0; i < sim.data()->ncon; ++i) {
        const mjContact& c = sim.data()->contact[i];
        EXPECT_FALSE((c.geom1 == crate && c.geom2 == ground) ||
                     (c.geom1 == ground && c.geom2 == crate));
      }
      return {contact, std::string(contact.target_name), sim.time() - t0};
    }
  }
  ADD_FAILURE() << "no contact with the crate";
  return {};
}

TEST(SimulationContactTest, AMoverCrossingThePathHitsTheRobotAndIsACollision) {
  // wider than the track (0.49 m): its front face (x = 1.3 - t) meets the front wheels, which stick
  // out beyond the chassis to x = 0.2255 + 0.0875, after 0.99 s
  const CrateHit wide = HitByCrate(1.0);
  EXPECT_NEAR(wide.time_s, 0.99, 0.01);
  EXPECT_EQ(wide.contact.part, RobotPart::kWheel);
  EXPECT_EQ(wide.target_name, "crate");
  EXPECT_EQ(wide.contact.target_index, 0);
  EXPECT_TRUE(IsCollision(wide.contact));
  EXPECT_DOUBLE_EQ(wide.contact.target_height_m, 0.6);
  EXPECT_NEAR(wide.contact.relative_speed_m_s, 1.0, 0.05);
  EXPECT_LT(wide.contact.normal_W.x(), -0.9);  // pushes the robot backwards

  // narrower than the gap between the wheels: it meets the chassis front (x = 0.28) after 1.02 s
  const CrateHit narrow = HitByCrate(0.3);
  EXPECT_NEAR(narrow.time_s, 1.02, 0.01);
  EXPECT_EQ(narrow.contact.part, RobotPart::kBody);
  EXPECT_EQ(narrow.contact.wheel, -1);
  EXPECT_EQ(narrow.target_name, "crate");
  EXPECT_TRUE(IsCollision(narrow.contact));
  EXPECT_NEAR(narrow.contact.relative_speed_m_s, 1.0, 0.05);
}

TEST(SimulationContactTest, DrivingIntoAWallIsACollisionAndOverRubbleIsNot) {
  TerrainWorld world = SmallFlatWorld();
  world.obstacles.push_back(Barrier("rubble", 1.0, 0.05));
  world.obstacles.push_back(Barrier("wall", 2.5, 0.5));
  Simulation dut(world, common::Pose2{}, Options());
  Drive(&dut, {0.5, 0.0});
  std::vector<RobotContact> contacts;
  std::set<std::string> touched;
  bool collided = false;
  double collision_x = 0.0;
  for (int step = 0; step < 3000 && !collided; ++step) {
    ASSERT_EQ(dut.Step(), StepStatus::kOk);
    dut.RobotContacts(&contacts);
    for (const RobotContact& contact : contacts) {
      if (contact.target != ContactTarget::kObstacle) continue;
      touched.insert(std::string(contact.target_name));
      EXPECT_EQ(contact.target_index, contact.target_name == "rubble" ? 0 : 1);
      if (IsCollision(contact)) {
        collided = true;
        collision_x = dut.State().X_WB.translation().x();
        EXPECT_EQ(contact.target_name, "wall");
        EXPECT_NEAR(contact.target_height_m, 0.5, 1e-9);
      } else {
        EXPECT_NEAR(contact.target_height_m, 0.05, 1e-9);
      }
    }
  }
  EXPECT_EQ(touched, (std::set<std::string>{"rubble", "wall"}));
  EXPECT_TRUE(collided);
  // the front wheels meet the wall's face at x = 2.4
  EXPECT_NEAR(collision_x, 2.4 - 0.2255 - 0.0875, 0.02);
}

TEST(SimulationContactTest, AWheelClimbsWhatItCanAndTheChassisPassesOverItsClearance) {
  RobotContact contact;
  contact.target = ContactTarget::kObstacle;
  contact.normal_W = Eigen::Vector3d(-1.0, 0.0, 0.0);  // a face, from the side
  for (const double height_m : {0.10, 0.14, 0.16, 0.17}) {
    contact.target_height_m = height_m;
    contact.part = RobotPart::kWheel;
    EXPECT_EQ(IsCollision(contact), height_m > kClimbableStep_m) << height_m;
    contact.part = RobotPart::kBody;
    EXPECT_EQ(IsCollision(contact), height_m > kDriveOverHeight_m) << height_m;
  }
  // from above (on top of it, or over a ledge's edge) nothing is a collision
  contact.normal_W = Eigen::Vector3d(-0.6, 0.0, 0.8);
  contact.target_height_m = 1.0;
  EXPECT_FALSE(IsCollision(contact));
  contact.target = ContactTarget::kMover;
  EXPECT_TRUE(IsCollision(contact));
}

TEST(SimulationContactTest, ATiltedSlabIsAsHighAsItIsWhereTheRobotTouchesIt) {
  // a 1 x 2 x 0.2 m slab tilted 10 deg about y, its near top edge 0.08 m above the ground at
  // x = 1 and its far one 0.25 m: its top above the ground under its centre is 0.25 m
  const double tilt = 10.0 * M_PI / 180.0;
  Obstacle slab;
  slab.name = "slab";
  slab.shape = ShapeType::kBox;
  slab.size = Eigen::Vector3d(0.5, 1.0, 0.1);
  slab.X_WO.linear() = Eigen::AngleAxisd(-tilt, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d near_top_O(-0.5, 0.0, 0.1);
  const double centre_z = 0.08 - (slab.X_WO.linear() * near_top_O).z();
  slab.X_WO.translation() =
      Eigen::Vector3d(1.0 - (slab.X_WO.linear() * near_top_O).x(), 0.0, centre_z);
  TerrainWorld world = SmallFlatWorld();
  world.obstacles.push_back(slab);
  Simulation dut(world, common::Pose2{}, Options());
  Drive(&dut, {0.5, 0.0});
  std::vector<RobotContact> contacts;
  for (int step = 0; step < 3000; ++step) {
    ASSERT_EQ(dut.Step(), StepStatus::kOk);
    dut.RobotContacts(&contacts);
    for (const RobotContact& contact : contacts) {
      if (contact.target != ContactTarget::kObstacle) continue;
      // the first touch: a front wheel at the near edge, 0.08 m high there (the top 1 cm inside
      // the face is 1.8 mm higher), not the 0.25 m of the slab's highest point
      EXPECT_EQ(contact.part, RobotPart::kWheel);
      EXPECT_GT(contact.target_height_m, 0.08 - 1e-3);
      EXPECT_LT(contact.target_height_m, 0.08 + 0.01 * std::tan(tilt) + 1e-3);
      EXPECT_FALSE(IsCollision(contact));
      return;
    }
  }
  ADD_FAILURE() << "the robot never touched the slab";
}

// The model's constraint rows (`<size njmax>`) are allocated as njmax^2 doubles and cleared on
// every load: they are sized to the worst contact this test makes (150 rows), with room to spare.
// The robot driven across a 45 deg slope rolls over and tumbles down it, chassis and wheels on the
// ground.
TEST(SimulationContactTest, ARobotTumblingDownASlopeStaysWithinTheModelsConstraintRows) {
  common::Pose2 start;
  start.position = Eigen::Vector2d(-5.0, -3.0);
  start.yaw = 0.5 * M_PI;
  Simulation dut(SlopeWorld(45.0), start, Options());
  Drive(&dut, {1.0, 0.0});
  double max_roll = 0.0;
  for (int i = 0; i < static_cast<int>(6.0 / dut.timestep()); ++i) {
    ASSERT_EQ(dut.Step(), StepStatus::kOk);
    max_roll = std::max(max_roll, std::abs(common::ToRollPitchYaw(dut.State().X_WB.linear()).roll));
  }
  EXPECT_GT(max_roll, 0.5 * M_PI);  // over on its side at least
  EXPECT_EQ(dut.warning_count(), 0) << (dut.warnings().empty() ? "" : dut.warnings().front());
  EXPECT_LE(4 * dut.data()->maxuse_efc, dut.model()->njmax);
}

TEST(SimulationMoverTest, AMoverIsWhereItWasPut) {
  const MovingObstacle crate = Crate({2.0, 1.0}, {0.0, 1.0});
  const TerrainWorld world = SmallFlatWorld();
  Simulation dut(world, common::Pose2{}, Options(), {crate});
  // at construction: its pose at t = 0
  EXPECT_EQ(dut.MoverPose(0).translation(), MoverPoseAt(crate, 0.0, world).translation());
  EXPECT_EQ(dut.MoverPose(0).translation(), Eigen::Vector3d(2.0, 1.0, 0.3));

  Eigen::Isometry3d X_WO = Eigen::Isometry3d::Identity();
  X_WO.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X_WO.translation() = Eigen::Vector3d(-2.0, 1.5, 0.4);
  dut.SetMoverPose(0, X_WO, Eigen::Vector2d(0.5, 0.0));
  ASSERT_EQ(dut.Step(), StepStatus::kOk);
  const int body = mj_name2id(dut.model(), mjOBJ_BODY, "mover_crate");
  ASSERT_GE(body, 0);
  const Eigen::Vector3d p_W(dut.data()->xpos + 3 * body);
  const Eigen::Matrix3d R_WO =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(dut.data()->xmat + 9 * body);
  EXPECT_EQ(p_W, X_WO.translation());
  EXPECT_TRUE(R_WO.isApprox(X_WO.linear(), 1e-12));
  EXPECT_TRUE(dut.MoverPose(0).isApprox(X_WO, 1e-12));
  EXPECT_EQ(dut.MoverVelocity(0), Eigen::Vector2d(0.5, 0.0));

  dut.SetMoverPoses(3.0);
  EXPECT_EQ(dut.MoverPose(0).translation(), Eigen::Vector3d(2.0, 4.0, 0.3));
  EXPECT_EQ(dut.MoverVelocity(0), Eigen::Vector2d(0.0, 1.0));
  EXPECT_THROW(dut.MoverPose(1), std::out_of_range);
  EXPECT_THROW(dut.SetMoverPose(-1, X_WO), std::out_of_range);
}

TEST(SimulationMoverTest, InvalidMoversAreInputErrors) {
  MovingObstacle crate = Crate({2.0, 1.0}, {0.0, 1.0});
  crate.half_height_m = -1.0;
  try {
    Simulation dut(SmallFlatWorld(), common::Pose2{}, Options(), {crate});
    FAIL() << "no error";
  } catch (const common::InputError& error) {
    EXPECT_STREQ(error.what(), "[0].half_height: value -1.000000 must be > 0 and finite");
  }
}

}  // namespace
}  // namespace trav::sim

namespace trav::sim {
namespace {

// A robot file without the IMU's sensors drives (no IMU readings) but is bad input when the IMU
// is asked for, naming both sensors.
TEST(RobotModelTest, TheImuSensorsAreRequiredOnlyWithTheImu) {
  std::ifstream scout(std::string(TRAV_MODELS_DIR) + "/scout_mini.xml");
  std::string xml((std::istreambuf_iterator<char>(scout)), std::istreambuf_iterator<char>());
  const std::size_t begin = xml.find("<sensor>");
  const std::size_t end = xml.find("</sensor>");
  ASSERT_NE(begin, std::string::npos);
  xml.erase(begin, end + std::string("</sensor>").size() - begin);
  // the Scout Mini's file names no other file, so it may live anywhere
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("trav_no_imu_" + std::to_string(getpid()) + ".xml"))
                               .string();
  std::ofstream(path) << xml;
  EXPECT_NO_THROW(ValidateRobotModel(path, false));
  try {
    ValidateRobotModel(path, true);
    ADD_FAILURE() << "no error without the IMU's sensors";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sensor 'imu_accel', sensor 'imu_gyro'"),
              std::string::npos)
        << e.what();
  }
  TerrainConfig config;
  config.type = TerrainType::kFlat;
  config.size_m = {8, 8};
  WorldOptions options;
  options.robot_model_path = path;
  const Simulation simulation(GenerateTerrain(config), common::Pose2{}, options);
  EXPECT_FALSE(simulation.ImuTruth().has_value());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace trav::sim
