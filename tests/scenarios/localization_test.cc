// One pose estimate for the whole stack: the mapper's input is in the estimate's odometry frame.
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "common/yaml_reader.h"
#include "scenarios/run/closed_loop.h"
#include "scenarios/run/scenario.h"
#include "scenarios/run/scenario_run.h"

namespace trav::scenarios {
namespace {

// Checks every frame the mapper gets against the frame in W and the step's truth and estimate.
class MapInputCheck : public LoopObserver {
 public:
  bool WantsPoints() const override { return true; }
  void OnLidarFrame(const ClosedLoop& /*loop*/, const lidar::LidarFrame& /*frame*/,
                    const Eigen::Matrix3Xf& points_W) override {
    points_W_ = points_W;
  }
  void OnMapInput(const ClosedLoop& loop, const common::PointCloud& cloud_O,
                  const Eigen::Isometry3d& X_OB, double /*t_s*/) override {
    ++frames_;
    EXPECT_TRUE(X_OB.isApprox(loop.estimate().X_WB, 0.0));
    const Eigen::Isometry3d X_OW = loop.estimate().X_WB * loop.state().X_WB.inverse();
    max_offset_m_ = std::max(max_offset_m_, X_OW.translation().norm());
    ASSERT_EQ(cloud_O.size(), points_W_.cols());  // no movers: nothing removed
    max_point_shift_m_ =
        std::max(max_point_shift_m_,
                 static_cast<double>((cloud_O.points - points_W_).cwiseAbs().maxCoeff()));
    for (Eigen::Index i = 0; i < cloud_O.size(); ++i) {
      ASSERT_TRUE(cloud_O.points.col(i).isApprox(
          (X_OW * points_W_.col(i).cast<double>()).cast<float>(), 1e-5f))
          << "frame " << frames_ << " point " << i;
    }
  }
  int frames_{0};
  double max_offset_m_{0.0};
  double max_point_shift_m_{0.0};  // largest change of a coordinate from W to O

 private:
  Eigen::Matrix3Xf points_W_;
};

Scenario Drive(const std::string& method) {
  return LoadScenario(common::YamlDocument::Parse(R"(
schema_version: 1
terrain: {type: hilly, size: [30, 30], seed: 3}
duration: 6
drive: [{v: 1.2, omega: 0.2, duration: 6}]
localization: {method: )" + method + R"(, translation_drift: 0.2, yaw_drift: 0.01}
video: {enabled: false}
)",
                                                  "drive.yaml"));
}

TEST(LocalizationTest, TheMapperGetsItsFramesInTheOdometryFrameOfThePoseEstimate) {
  const Scenario scenario = Drive("drift-model");
  ClosedLoop loop(scenario, {RobotModelPath(scenario, TRAV_MODELS_DIR), 0});
  MapInputCheck check;
  loop.AddObserver(&check);
  loop.Run();
  EXPECT_GE(check.frames_, 55);
  // 7 m at 0.2 m/sqrt(m): the frames were moved by tens of centimetres
  EXPECT_GT(check.max_offset_m_, 0.05);
  EXPECT_GT(check.max_point_shift_m_, 0.05);
  ASSERT_FALSE(loop.map_updates().empty());
}

TEST(LocalizationTest, WithTheTruePoseTheMapperGetsTheFramesInTheWorldFrame) {
  const Scenario scenario = Drive("true");
  ClosedLoop loop(scenario, {RobotModelPath(scenario, TRAV_MODELS_DIR), 0});
  MapInputCheck check;
  loop.AddObserver(&check);
  loop.Run();
  EXPECT_GE(check.frames_, 55);
  EXPECT_EQ(check.max_point_shift_m_, 0.0);
}

}  // namespace
}  // namespace trav::scenarios
