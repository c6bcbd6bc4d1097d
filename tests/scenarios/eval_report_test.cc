#include "scenarios/experiments/eval_report.h"

#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/input_error.h"
#include "scenarios/experiments/evaluation.h"

namespace trav::scenarios {
namespace {

// A scene record as RunEvalScene writes it, with one method.
EvalSceneRecord Scene(const std::string& terrain, const std::string& method,
                      std::optional<double> mean, double variance, std::vector<double> runtimes_ms,
                      double memory_mb) {
  EvalSceneRecord scene;
  scene.terrain = terrain;
  scene.drive.frames = runtimes_ms.size();
  EvalMethodRecord& record = scene.methods[method];
  record.mean_error = mean;
  record.error_variance = variance;
  record.peak_memory_mb = memory_mb;
  record.coverage = 0.5;
  record.frames.runtime_ms = std::move(runtimes_ms);
  return scene;
}

TEST(AggregateScenesTest, AveragesScenesAndTakesTheMedianOverEveryFrame) {
  const std::vector<EvalSceneRecord> scenes = {
      Scene("hilly", "em", 0.1, 0.01, {1.0, 5.0}, 2.0),
      Scene("hilly", "em", 0.3, 0.03, {2.0, 3.0, 4.0}, 3.0),
      Scene("hilly", "em", std::nullopt, 0.0, {9.0}, 9.0),  // no scored frame: left out
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
  // a row reads back from results.json
  const nlohmann::json row = rows[0];
  EXPECT_EQ(row.at("scenes"), 2);
  EXPECT_EQ(nlohmann::json(row.get<EvalAggregate>()), row);
}

TEST(EvalSceneRecordTest, RoundTripsThroughJsonWithMissingErrorsAsNull) {
  EvalSceneRecord scene;
  scene.id = "hilly-3";
  scene.terrain = "hilly";
  scene.seed = 3;
  scene.route = {{-1.0, 2.0, 0.5}, {1.0, -2.0}, 4.5, 2.75, 3};
  scene.drive = {"success", 12.5, 4.75, 2, 250000};
  EvalMethodRecord& em = scene.methods["em"];
  em.mean_error = 0.25;
  em.error_variance = 0.0625;
  em.scored_frames = 1;
  em.runtime_ms_median = 1.5;
  em.runtime_ms_max = 2.0;
  em.peak_memory_mb = 3.0;
  em.coverage = 0.75;
  em.wall_ms_median = 4.5;
  em.hazards.auroc = 0.875;
  em.hazards.hazard_cells = 1;
  em.hazards.compared_cells = 3;
  em.hazards.cost_truth_histogram = {{10, 12, 2}, {95, 99, 1}};
  em.frames = {{0.1, 0.2},
               {std::nullopt, 0.25},
               {std::nullopt, 0.0625},
               {0, 3},
               {2, 4},
               {1.0, 2.0},
               {3.0, 6.0},
               {0.5, 1.0}};
  scene.methods["sgp"].frames.t_s = {0.1};  // scored no frame
  const nlohmann::json json = scene;
  EXPECT_EQ(json.at("route").dump(),
            R"({"draws":3,"goal":[1.0,-2.0],"length_m":2.75,"optimal_length_m":4.5,)"
            R"("start":[-1.0,2.0,0.5]})");
  EXPECT_EQ(json.at("drive").dump(), R"({"distance_m":4.75,"frames":2,"ground_truth_cells":250000,)"
                                     R"("outcome":"success","sim_time_s":12.5})");
  EXPECT_EQ(json.at("methods").at("em").at("frames").at("mean_error").dump(), "[null,0.25]");
  EXPECT_TRUE(json.at("methods").at("sgp").at("mean_error").is_null());
  EXPECT_TRUE(json.at("methods").at("sgp").at("frames").at("mean_error").is_array());
  const nlohmann::json& em_json = json.at("methods").at("em");
  EXPECT_EQ(em_json.at("auroc"), 0.875);
  EXPECT_TRUE(em_json.at("average_precision").is_null());
  EXPECT_EQ(em_json.at("cpu_ms_median"), 1.5);
  EXPECT_EQ(em_json.at("wall_ms_median"), 4.5);
  EXPECT_EQ(em_json.at("cost_truth_histogram").dump(), "[[10,12,2],[95,99,1]]");
  EXPECT_EQ(em_json.at("frames").at("wall_ms").dump(), "[3.0,6.0]");

  const EvalSceneRecord back = nlohmann::json::parse(json.dump(1)).get<EvalSceneRecord>();
  EXPECT_EQ(nlohmann::json(back), json);
  EXPECT_FALSE(back.methods.at("sgp").mean_error.has_value());
  ASSERT_TRUE(back.methods.at("em").frames.mean_error[1].has_value());
  EXPECT_EQ(*back.methods.at("em").frames.mean_error[1], 0.25);
  // a record without its methods is not a finished scene
  nlohmann::json partial = json;
  partial.erase("methods");
  EXPECT_THROW(partial.get<EvalSceneRecord>(), nlohmann::json::exception);
}

TEST(EvalMetricsTest, CalibrationMapsEachCostToTheOtherScenesMeanTruthMonotonically) {
  HazardScores scene;
  scene.cost_truth_histogram = {{10, 10, 2}, {90, 100, 1}};
  HazardScores other;
  other.cost_truth_histogram = {{10, 20, 1}, {90, 90, 1}};
  CostTruthSums others;
  AddCells(other, 1, &others);
  // f(0.1) = 0.2, f(0.9) = 0.9: (2 x 0.1 + 1 x 0.1) / 3 cells
  EXPECT_DOUBLE_EQ(*CalibratedMae(scene, others), 0.1);
  // a scene's own cells taken back out of a total leave exactly the others'
  CostTruthSums all = others;
  AddCells(scene, 1, &all);
  AddCells(scene, -1, &all);
  EXPECT_DOUBLE_EQ(*CalibratedMae(scene, all), 0.1);
  // a cost that falls as the truth rises is pooled into one level, 0.5
  HazardScores inverse;
  inverse.cost_truth_histogram = {{10, 80, 1}, {90, 20, 1}};
  CostTruthSums inverted;
  AddCells(inverse, 1, &inverted);
  EXPECT_DOUBLE_EQ(*CalibratedMae(scene, inverted), (2 * 0.4 + 0.5) / 3.0);
  EXPECT_FALSE(CalibratedMae(scene, {}).has_value());
}

TEST(EvalMetricsTest, PairedDifferencesClaimOnlyWhereTheIntervalExcludesZeroOverFiveScenes) {
  std::vector<SceneMetrics> method, reference;
  for (int i = 0; i < 5; ++i) {
    SceneMetrics m, r;
    m.id = r.id = "s" + std::to_string(i);
    m.auroc = 0.9;
    r.auroc = 0.8;
    m.mean_error = 0.3;
    r.mean_error = 0.2;
    m.spearman = 0.5 + 0.1 * (i % 2);  // differences +0.1 and -0.1: not settled
    r.spearman = 0.55;
    method.push_back(m);
    reference.push_back(r);
  }
  reference[4].mean_error.reset();  // a metric missing in a scene drops that scene's pair
  const std::vector<PairedDifference> differences = PairedDifferences(method, reference);
  ASSERT_EQ(differences.size(), 3u);
  EXPECT_EQ(differences[0].metric, "mean_error");
  EXPECT_EQ(differences[0].scenes, 4);
  EXPECT_EQ(differences[0].verdict, "not settled");  // four scenes are too few for a claim
  EXPECT_EQ(differences[1].metric, "auroc");
  EXPECT_NEAR(differences[1].mean, 0.1, 1e-12);
  EXPECT_NEAR(differences[1].low, 0.1, 1e-12);
  EXPECT_EQ(differences[1].verdict, "better");
  EXPECT_EQ(differences[2].metric, "spearman");
  EXPECT_EQ(differences[2].verdict, "not settled");
  reference[4].mean_error = 0.2;
  EXPECT_EQ(PairedDifferences(method, reference)[0].verdict, "worse");  // a higher error
}

TEST(EvalOptionsTest, AblationAddsTheOtherInducingPointCounts) {
  EvalOptions options;
  options.methods = {"fsgp-bgk", "em"};
  options.inducing_points = {50, 125, 500};
  EXPECT_EQ(BaseInducingPoints(options), 500);
  EXPECT_EQ(EvalMethods(options),
            (std::vector<std::string>{"fsgp-bgk", "em", "constant=0.5", "ground-truth",
                                      "fsgp-bgk-m50", "fsgp-bgk-m125"}));
  options.sets = {"mapping.max_training_points=125"};
  EXPECT_EQ(EvalMethods(options),
            (std::vector<std::string>{"fsgp-bgk", "em", "constant=0.5", "ground-truth",
                                      "fsgp-bgk-m50", "fsgp-bgk-m500"}));
  options.methods = {"constant=0.2", "ground-truth"};
  options.inducing_points = {};
  EXPECT_EQ(EvalMethods(options), (std::vector<std::string>{"constant=0.2", "ground-truth"}));
  // the paper's ablation: every GP mapper among the methods, in their order
  options.methods = {"em", "fsgp-bgk", "sgp", "fsgp-accumulation"};
  options.inducing_points = {50, 500};
  options.sets.clear();
  EXPECT_EQ(AblatedMethods(options), (std::vector<std::string>{"fsgp-bgk", "sgp"}));
  EXPECT_EQ(EvalMethods(options),
            (std::vector<std::string>{"em", "fsgp-bgk", "sgp", "fsgp-accumulation", "constant=0.5",
                                      "ground-truth", "fsgp-bgk-m50", "sgp-m50"}));
}

TEST(EvalOptionsTest, AblationMethodNamesParseBackToTheirMapperAndCount) {
  const std::optional<AblationMethod> fsgp_bgk = ParseAblationMethod("fsgp-bgk-m50");
  ASSERT_TRUE(fsgp_bgk.has_value());
  EXPECT_EQ(fsgp_bgk->base, "fsgp-bgk");
  EXPECT_EQ(fsgp_bgk->inducing_points, 50);
  EXPECT_EQ(fsgp_bgk->Name(), "fsgp-bgk-m50");
  const std::optional<AblationMethod> fsgp = ParseAblationMethod("fsgp-m125");
  ASSERT_TRUE(fsgp.has_value());
  EXPECT_EQ(fsgp->base, "fsgp");
  EXPECT_EQ(fsgp->inducing_points, 125);
  EXPECT_EQ(ParseAblationMethod("sgp-m500")->base, "sgp");
  for (const char* other : {"fsgp-bgk", "em-m50", "fsgp-accumulation-m50", "fsgp-bgk-no-features",
                            "sgp-m", "sgp-m5x", "constant=0.5"}) {
    EXPECT_FALSE(ParseAblationMethod(other).has_value()) << other;
  }
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
