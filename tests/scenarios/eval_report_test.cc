#include "scenarios/experiments/eval_report.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/input_error.h"
#include "scenarios/experiments/evaluation.h"

namespace trav::scenarios {
namespace {

// A scene record as RunEvalScene writes it, with one method.
nlohmann::json Scene(const std::string& terrain, const std::string& method, nlohmann::json mean,
                     double variance, std::vector<double> runtimes_ms, double memory_mb) {
  return {{"terrain", terrain},
          {"drive", {{"frames", runtimes_ms.size()}}},
          {"methods",
           {{method,
             {{"mean_error", mean},
              {"error_variance", variance},
              {"peak_memory_mb", memory_mb},
              {"coverage", 0.5},
              {"frames", {{"runtime_ms", runtimes_ms}}}}}}}};
}

TEST(AggregateScenesTest, AveragesScenesAndTakesTheMedianOverEveryFrame) {
  const std::vector<nlohmann::json> scenes = {
      Scene("hilly", "em", 0.1, 0.01, {1.0, 5.0}, 2.0),
      Scene("hilly", "em", 0.3, 0.03, {2.0, 3.0, 4.0}, 3.0),
      Scene("hilly", "em", nullptr, 0.0, {9.0}, 9.0),  // no scored frame: left out
      Scene("forest", "em", 0.5, 0.05, {7.0}, 1.0),
  };
  const std::vector<EvalAggregate> rows = AggregateScenes(scenes, {"hilly", "forest"}, {"em"});
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].terrain, "hilly");
  EXPECT_EQ(rows[0].scenes, 2);
  EXPECT_EQ(rows[0].frames, 5);
  EXPECT_DOUBLE_EQ(rows[0].mean_error, 0.2);
  EXPECT_DOUBLE_EQ(rows[0].error_variance, 0.02);
  EXPECT_DOUBLE_EQ(rows[0].runtime_ms_median, 3.0);  // of 1, 2, 3, 4, 5
  EXPECT_DOUBLE_EQ(rows[0].peak_memory_mb, 3.0);
  EXPECT_DOUBLE_EQ(rows[0].coverage, 0.5);
  EXPECT_EQ(rows[1].terrain, "forest");
  EXPECT_DOUBLE_EQ(rows[1].mean_error, 0.5);
  // a method no scene ran has no row
  EXPECT_TRUE(AggregateScenes(scenes, {"hilly"}, {"sgp"}).empty());
}

TEST(EvalOptionsTest, AblationAddsTheOtherInducingPointCounts) {
  EvalOptions options;
  options.methods = {"fsgp-bgk", "em"};
  options.inducing_points = {50, 125, 500};
  EXPECT_EQ(BaseInducingPoints(options), 500);
  EXPECT_EQ(EvalMethods(options),
            (std::vector<std::string>{"fsgp-bgk", "em", "fsgp-bgk-m50", "fsgp-bgk-m125"}));
  options.sets = {"mapping.max_training_points=125"};
  EXPECT_EQ(EvalMethods(options),
            (std::vector<std::string>{"fsgp-bgk", "em", "fsgp-bgk-m50", "fsgp-bgk-m500"}));
}

TEST(EvalOptionsTest, ScenesAreSeededPerTerrainType) {
  EvalOptions options;
  options.terrains = {"hilly", "road"};
  options.scenes = 2;
  options.seed = 10;
  const std::vector<EvalScene> scenes = EvalScenes(options);
  ASSERT_EQ(scenes.size(), 4u);
  EXPECT_EQ(scenes[0].Id(), "hilly-10");
  EXPECT_EQ(scenes[1].Id(), "hilly-11");
  EXPECT_EQ(scenes[3].Id(), "road-11");
}

TEST(EvalOptionsTest, RoundTripsThroughJsonAndResumesOnlyTheSameEvaluation) {
  EvalOptions options;
  options.methods = {"em", "constant=0.5"};
  options.sets = {"lidar.occlusion=0.2"};
  const EvalOptions back = EvalOptionsFromJson(EvalOptionsJson(options), "options.json");
  EXPECT_TRUE(SameEvaluation(options, back));
  EvalOptions more_jobs = back;
  more_jobs.jobs = 7;
  EXPECT_TRUE(SameEvaluation(options, more_jobs));
  EvalOptions other_seed = back;
  other_seed.seed = 2;
  EXPECT_FALSE(SameEvaluation(options, other_seed));
  EXPECT_THROW(EvalOptionsFromJson({{"scenes", 2}}, "options.json"), common::InputError);
}

TEST(EvalOptionsTest, ValidationNamesTheFlagAndValue) {
  EvalOptions options;
  EXPECT_NO_THROW(ValidateEvalOptions(options));
  options.methods = {"em", "em"};
  try {
    ValidateEvalOptions(options);
    FAIL() << "a method listed twice was accepted";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--methods"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trav::scenarios
