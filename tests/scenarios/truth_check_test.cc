#include "scenarios/run/truth_check.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace trav::scenarios {
namespace {

const std::string kRobotModel = std::string(TRAV_MODELS_DIR) + "/scout_mini.xml";

std::vector<TruthCheckSample> Check(sim::TerrainConfig terrain, int samples) {
  TruthCheckOptions options;
  options.terrain = terrain;
  options.samples = samples;
  return CheckPhysicalTruth(options, kRobotModel, controller::SkidSteerConfig{},
                            mapping::GroundTruthConfig{});
}

// The physical truth agrees with the robot in MuJoCo on a ruin (rubble, columns, hills): half the
// drives predicted traversable, half not; the full figures (300 per terrain type) are in
// docs/ground-truth.md.
TEST(TruthCheckTest, TheTruthAgreesWithTheRobotOnARuin) {
  sim::TerrainConfig ruin;
  ruin.type = sim::TerrainType::kRuin;
  ruin.seed = 1;
  const std::vector<TruthCheckSample> samples = Check(ruin, 20);
  const TruthCheckSummary summary = Summarize("ruin", samples);
  EXPECT_EQ(summary.samples, 20);
  EXPECT_EQ(summary.predicted_traversable, 10);
  EXPECT_GE(summary.Agreement(), 0.9);
  // what the robot did is recorded for every sample
  for (const TruthCheckSample& sample : samples) {
    if (sample.result == DriveResult::kCrossed) {
      EXPECT_GE(sample.moved_m, 1.0);
    }
    if (sample.result == DriveResult::kTipped) {
      EXPECT_GT(sample.max_tilt_deg, kTippedTilt_deg);
    }
  }
}

// A 0.10 m step is within every limit whichever way the robot meets it; it crosses it every time.
TEST(TruthCheckTest, ALowStepIsCrossedFromEveryHeading) {
  sim::TerrainConfig step;
  step.type = sim::TerrainType::kStep;
  step.step.height_m = 0.10;
  step.step.x_m = 0.0;
  const std::vector<TruthCheckSample> samples = Check(step, 10);
  const TruthCheckSummary summary = Summarize("step", samples);
  // no drive is predicted untraversable, so only the traversable half is drawn
  EXPECT_EQ(summary.samples, 5);
  EXPECT_EQ(summary.predicted_traversable, 5);
  EXPECT_EQ(summary.agree_traversable, 5);
}

}  // namespace
}  // namespace trav::scenarios
