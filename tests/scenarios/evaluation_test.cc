// End-to-end tests of `trav eval`: the tables, plots and records it writes, exact scores for an
// oracle and a constant method, resuming, failed scenes, and bad arguments.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/stat.h>
#include <sys/wait.h>

#include "scenarios/experiments/eval_report.h"
#include "tests/cli_test_util.h"

// Clang says whether AddressSanitizer is on through __has_feature, GCC through
// __SANITIZE_ADDRESS__.
#if defined(__has_feature)
#define TRAV_HAS_ADDRESS_SANITIZER __has_feature(address_sanitizer)
#else
#define TRAV_HAS_ADDRESS_SANITIZER 0
#endif

namespace trav::scenarios {
namespace {

namespace fs = std::filesystem;
using test_util::CommandResult;
using test_util::ReadFile;
using test_util::RunTrav;
using ::testing::HasSubstr;

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream file(path);
  return nlohmann::json::parse(file);
}

// The record of `method` in results.json.
EvalAggregate Record(const nlohmann::json& results, const std::string& method) {
  for (const EvalAggregate& record : results.get<std::vector<EvalAggregate>>()) {
    if (record.method == method) return record;
  }
  ADD_FAILURE() << "no record for " << method;
  return {};
}

class EvaluationTest : public ::testing::Test {
 protected:
  void SetUp() override { root_ = test_util::FreshTestFolder("trav_eval_test"); }
  void TearDown() override { fs::remove_all(root_); }

  // Two short scenes on flat ground (ground truth 0 everywhere), with the oracle, a constant, and
  // SGP and FSGP-BGK with a two-point ablation.
  std::string TinyEval() const {
    return "eval --out " + (root_ / "eval").string() +
           " --terrains flat --scenes 2 --seed 5 --frames 6 --jobs 2"
           " --methods ground-truth,constant=0.25,sgp,fsgp-bgk --inducing 50,500";
  }

  // Flat ground with one crate between start and goal (the only hazards of the truth), 6 m
  // routes, `scenes` scenes from seed 5, 6 frames each, `methods` without the ablation.
  CommandResult CrateEval(int scenes, const std::string& methods) const {
    return RunTrav("eval --out " + (root_ / "eval").string() + " --terrains flat --scenes " +
                   std::to_string(scenes) +
                   " --seed 5 --frames 6 --jobs 2 --route-length 6 --no-ablation --methods " +
                   methods +
                   " --set 'terrain.boxes=[{name: crate, centre: [0, 0], half_extents: [0.4, "
                   "0.4], height: 1}]'");
  }

  fs::path root_;
};

TEST_F(EvaluationTest, WritesEveryTableAndPlotAndScoresTheOracleAndAConstantExactly) {
  const CommandResult run = RunTrav(TinyEval());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const fs::path out = root_ / "eval";
  for (const char* file :
       {"options.json", "results.json", "results.csv", "results.md", "error_over_time_flat.csv",
        "ablation.csv", "ablation_methods.csv", "scenes/flat-5.json", "scenes/flat-6.json"}) {
    EXPECT_TRUE(fs::is_regular_file(out / file)) << file;
  }
  if (access("/usr/bin/gnuplot", X_OK) == 0) {
    for (const char* plot :
         {"error_over_time_flat.png", "ablation_error.png", "ablation_runtime.png"}) {
      EXPECT_GT(fs::file_size(out / plot), 1000u) << plot;
    }
  }

  // one record per terrain type and method, with the interface's fields
  const nlohmann::json results = ReadJson(out / "results.json");
  // ground-truth, constant, sgp, fsgp-bgk, and the ablation's sgp-m50 and fsgp-bgk-m50
  ASSERT_EQ(results.size(), 6u);
  for (const nlohmann::json& record : results) {
    for (const char* field : {"terrain", "method", "mean_error", "error_variance",
                              "runtime_ms_median", "peak_memory_mb"}) {
      EXPECT_TRUE(record.contains(field)) << field;
    }
    EXPECT_EQ(record.at("terrain"), "flat");
    EXPECT_EQ(record.at("scenes"), 2);
    EXPECT_EQ(record.at("frames"), 12);
  }
  const EvalAggregate oracle = Record(results, "ground-truth");
  EXPECT_EQ(oracle.mean_error, 0.0);
  EXPECT_EQ(oracle.error_variance, 0.0);
  EXPECT_EQ(oracle.coverage, 1.0);
  const EvalAggregate constant = Record(results, "constant=0.25");
  EXPECT_EQ(constant.mean_error, 0.25);
  EXPECT_EQ(constant.error_variance, 0.0);
  // FSGP-BGK on flat ground: nearly free everywhere, in a few milliseconds
  const EvalAggregate fsgp_bgk = Record(results, "fsgp-bgk");
  EXPECT_LT(fsgp_bgk.mean_error, 0.05);
  EXPECT_GT(fsgp_bgk.runtime_ms_median, 0.0);
#if !defined(__SANITIZE_ADDRESS__) && !TRAV_HAS_ADDRESS_SANITIZER
  // glibc's mallinfo2 sees nothing of AddressSanitizer's allocator (scripts/test --sanitize)
  EXPECT_GT(fsgp_bgk.peak_memory_mb, 0.0);
#endif
  EXPECT_EQ(Record(results, "fsgp-bgk-m50").scenes, 2);
  EXPECT_EQ(Record(results, "sgp-m50").scenes, 2);
  // the paper's ablation: each GP mapper at each M, the scenes' own M (500) being the method itself
  const std::string ablation = ReadFile(out / "ablation_methods.csv");
  EXPECT_THAT(ablation, testing::StartsWith("method,inducing_points,flat_error,flat_auroc,"));
  for (const char* row : {"\nsgp,50,", "\nsgp,500,", "\nfsgp-bgk,50,", "\nfsgp-bgk,500,"}) {
    EXPECT_THAT(ablation, HasSubstr(row));
  }

  // each scene keeps its per-frame numbers
  const nlohmann::json scene = ReadJson(out / "scenes/flat-5.json");
  EXPECT_EQ(scene.at("terrain"), "flat");
  EXPECT_EQ(scene.at("drive").at("frames"), 6);
  const nlohmann::json& frames = scene.at("methods").at("ground-truth").at("frames");
  EXPECT_EQ(frames.at("mean_error").size(), 6u);
  EXPECT_GT(frames.at("observed_cells").back().get<int>(), 100);
  EXPECT_EQ(frames.at("compared_cells"), frames.at("observed_cells"));

  // the markdown holds the paper's tables next to ours
  std::ifstream md_file(out / "results.md");
  std::stringstream md;
  md << md_file.rdbuf();
  for (const char* heading : {"Table I", "Table II", "Table III", "Inducing-point ablation"}) {
    EXPECT_THAT(md.str(), HasSubstr(heading));
  }
  EXPECT_THAT(md.str(), HasSubstr("0.1237 / 0.0085"));  // the paper's FSGP-BGK on hilly
  EXPECT_THAT(md.str(), HasSubstr("| flat | 0.0000 / 0.0000 | 0.2500 / 0.0000 |"));
}

// The crate world (CrateEval): the oracle ranks every hazard first, a constant cannot rank.
TEST_F(EvaluationTest, RanksTheHazardsWithTheOracleAtOneAndAConstantAtOneHalf) {
  const CommandResult run = CrateEval(2, "fsgp-bgk,em");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json results = ReadJson(root_ / "eval" / "results.json");
  ASSERT_EQ(results.size(), 4u);  // fsgp-bgk, em, and the floor and ceiling added to every table
  for (const nlohmann::json& record : results) {
    for (const char* field : {"auroc", "average_precision", "spearman", "calibrated_mae",
                              "elevation_rmse", "cpu_ms_median", "wall_ms_median"}) {
      EXPECT_TRUE(record.contains(field)) << field;
    }
    EXPECT_EQ(record.at("scene_values").size(), 2u);
  }
  const EvalAggregate oracle = Record(results, "ground-truth");
  EXPECT_EQ(oracle.auroc, 1.0);
  EXPECT_EQ(oracle.average_precision, 1.0);
  EXPECT_FALSE(oracle.elevation_rmse.has_value());  // the oracle paints costs only
  const EvalAggregate constant = Record(results, "constant=0.5");
  EXPECT_EQ(constant.auroc, 0.5);
  EXPECT_FALSE(constant.spearman.has_value());
  EXPECT_EQ(constant.paired_with, "fsgp-bgk");
  const EvalAggregate fsgp_bgk = Record(results, "fsgp-bgk");
  EXPECT_TRUE(fsgp_bgk.paired.empty());
  EXPECT_GT(fsgp_bgk.runtime_ms_median, 0.0);
  for (const nlohmann::json& record : results) {
    EXPECT_EQ(record.at("cpu_ms_median"), record.at("runtime_ms_median"));  // one CPU figure
  }
  ASSERT_TRUE(fsgp_bgk.elevation_rmse.has_value());
  EXPECT_LT(*fsgp_bgk.elevation_rmse, 0.1);
  // every compared metric of the constant against FSGP-BGK, over the two scenes
  ASSERT_FALSE(constant.paired.empty());
  for (const PairedDifference& d : constant.paired) {
    EXPECT_EQ(d.scenes, 2) << d.metric;
    EXPECT_LE(d.low, d.mean) << d.metric;
    EXPECT_GE(d.high, d.mean) << d.metric;
  }
  const std::string md = ReadFile(root_ / "eval" / "results.md");
  EXPECT_THAT(md, HasSubstr("Ground truth: **physical**"));
  EXPECT_EQ(ReadJson(root_ / "eval" / "options.json").at("truth"), "physical");
  EXPECT_THAT(md, HasSubstr("## Finding hazards"));
  EXPECT_THAT(md, HasSubstr("## Paired differences"));
  const nlohmann::json scene = ReadJson(root_ / "eval" / "scenes" / "flat-5.json");
  EXPECT_EQ(scene.at("route").at("length_m"), 6.0);
  EXPECT_GE(scene.at("route").at("draws"), 1);
}

// The geometric truth on request: its own threshold (the planner's lethal cost) makes the crate's
// cells the hazards, so the oracle still ranks them perfectly; evaluations written before the
// physical truth existed read back as geometric.
TEST_F(EvaluationTest, TheGeometricTruthIsAFlagAwayAndOlderFoldersReadAsIt) {
  const CommandResult run = RunTrav(
      "eval --out " + (root_ / "eval").string() +
      " --terrains flat --scenes 1 --seed 5 --frames 6 --jobs 1 --route-length 6 --no-ablation"
      " --methods fsgp-bgk --truth geometric --set 'terrain.boxes=[{name: crate, centre: [0, 0],"
      " half_extents: [0.4, 0.4], height: 1}]'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(ReadFile(root_ / "eval" / "results.md"), HasSubstr("Ground truth: **geometric**"));
  const nlohmann::json results = ReadJson(root_ / "eval" / "results.json");
  EXPECT_EQ(Record(results, "ground-truth").auroc, 1.0);
  nlohmann::json options = ReadJson(root_ / "eval" / "options.json");
  EXPECT_EQ(options.at("truth"), "geometric");
  // the flag changes what is scored: on a forest the two truths call different cells untraversable
  // (the physical one only where no heading of the robot fits, the geometric one every cell with a
  // trunk or a steep patch), on the same frames
  auto forest_hazards = [&](const std::string& folder, const std::string& truth) {
    const CommandResult forest =
        RunTrav("eval --out " + (root_ / folder).string() +
                " --terrains forest --scenes 1 --frames 10 --jobs 1 --no-ablation --methods "
                "fsgp-bgk" +
                truth);
    EXPECT_EQ(forest.exit_code, 0) << forest.output;
    return ReadJson(root_ / folder / "scenes" / "forest-1.json")
        .at("methods")
        .at("fsgp-bgk")
        .at("hazard_cells")
        .get<int>();
  };
  EXPECT_NE(forest_hazards("forest_geometric", " --truth geometric"),
            forest_hazards("forest_physical", ""));
  options.erase("truth");
  EXPECT_EQ(EvalOptionsFromJson(options, "options.json").truth, "geometric");
}

// The ablations of the paper's contributions: the fixed-gain filter fuses with FSGP-BGK's own mean
// weight of the scene (that the mapper uses the gain is FsgpBgkMapperTest's), the GP without
// (kappa, g) inputs maps the same frames differently.
TEST_F(EvaluationTest, TheContributionAblationsRunBesideFsgpBgk) {
  const CommandResult run = CrateEval(1, "fsgp-bgk-fixed-gain,fsgp-bgk,fsgp-bgk-no-features");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json methods = ReadJson(root_ / "eval" / "scenes" / "flat-5.json").at("methods");
  const double bgk_weight = methods.at("fsgp-bgk").at("mean_fusion_weight").get<double>();
  EXPECT_GT(bgk_weight, 0.0);
  EXPECT_NEAR(methods.at("fsgp-bgk-fixed-gain").at("mean_fusion_weight").get<double>(), bgk_weight,
              1e-9 * bgk_weight);
  // without the feature inputs the GP maps the same frames differently
  EXPECT_TRUE(methods.at("fsgp-bgk-no-features").at("mean_error").is_number());
  EXPECT_NE(methods.at("fsgp-bgk-no-features").at("frames").at("mean_error"),
            methods.at("fsgp-bgk").at("frames").at("mean_error"));
  EXPECT_TRUE(methods.at("constant=0.5").at("mean_fusion_weight").is_null());
  EXPECT_EQ(
      RunTrav("eval --out " + (root_ / "bad").string() + " --methods fsgp-bgk-no-gain").exit_code,
      2);
}

// FSGP beside FSGP-BGK fuses FSGP-BGK's regression (FsgpBgkMapper::UnfusedOf), and the ablation's
// FSGP-BGK and FSGP at M = 50 sample the features of those at the base M (OnFeaturesOf): the
// scores of each are those of its method evaluated alone at its M, number for number.
TEST_F(EvaluationTest, MappersSharingWorkScoreAsTheirMethodsAlone) {
  auto eval = [&](const std::string& folder, const std::string& methods,
                  const std::string& options) {
    const CommandResult run = RunTrav(
        "eval --out " + (root_ / folder).string() +
        " --terrains flat --scenes 1 --seed 5 --frames 6 --jobs 1 --route-length 6 --methods " +
        methods + " " + options +
        " --set 'terrain.boxes=[{name: crate, centre: [0, 0], half_extents: [0.4, 0.4], height: "
        "1}]'");
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return ReadJson(root_ / folder / "scenes" / "flat-5.json").at("methods");
  };
  const nlohmann::json together = eval("together", "fsgp,fsgp-bgk", "--inducing 50,500");
  const nlohmann::json fsgp = eval("fsgp", "fsgp", "--no-ablation");
  const std::string at_50 = "--no-ablation --set mapping.max_training_points=50";
  const nlohmann::json fsgp_50 = eval("fsgp_50", "fsgp", at_50);
  const nlohmann::json bgk_50 = eval("bgk_50", "fsgp-bgk", at_50);
  for (const auto& [method, alone] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"fsgp", fsgp.at("fsgp")},
           {"fsgp-m50", fsgp_50.at("fsgp")},
           {"fsgp-bgk-m50", bgk_50.at("fsgp-bgk")}}) {
    for (const std::string key : {"mean_error", "error_variance", "scored_frames", "coverage",
                                  "auroc", "average_precision", "cost_truth_histogram"}) {
      EXPECT_EQ(together.at(method).at(key), alone.at(key)) << method << " " << key;
    }
    for (const std::string key : {"mean_error", "compared_cells", "observed_cells"}) {
      EXPECT_EQ(together.at(method).at("frames").at(key), alone.at("frames").at(key))
          << method << " " << key;
    }
    EXPECT_EQ(together.at(method).at("frames").at("runtime_ms").size(), 6u);
  }
  // the crate is seen: the maps are scored against hazards; the methods' maps differ
  EXPECT_GT(fsgp.at("fsgp").at("hazard_cells").get<int>(), 0);
  EXPECT_NE(together.at("fsgp").at("frames").at("mean_error"),
            together.at("fsgp-bgk").at("frames").at("mean_error"));
  EXPECT_NE(together.at("fsgp-bgk-m50").at("frames").at("mean_error"),
            together.at("fsgp-bgk").at("frames").at("mean_error"));
}

// The mappers on the drift model's pose: the same drive's frames moved into the estimate's
// odometry frame. With no drift the moved frames are the frames, so the maps are the same.
TEST_F(EvaluationTest, ThePoseSourcesRunEveryMapperOnTheEstimatesFrames) {
  const CommandResult run = RunTrav(
      "eval --out " + (root_ / "eval").string() +
      " --terrains flat --scenes 1 --seed 5 --frames 6 --jobs 1 --route-length 6 --no-ablation "
      "--methods fsgp-bgk,em,ground-truth --pose-sources drift-model,scan-matching --set "
      "'terrain.boxes=[{name: crate, centre: [0, 0], half_extents: [0.4, 0.4], height: 0.6}]' "
      "--set localization.translation_drift=0.5 --set localization.yaw_drift=0.05");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json methods = ReadJson(root_ / "eval" / "scenes" / "flat-5.json").at("methods");
  // every mapper of --methods, not the oracle or the floor
  EXPECT_TRUE(methods.contains("fsgp-bgk@drift-model"));
  EXPECT_TRUE(methods.contains("em@drift-model"));
  EXPECT_TRUE(methods.contains("fsgp-bgk@scan-matching"));
  EXPECT_EQ(methods.at("em@scan-matching").at("frames").at("t_s").size(), 6u);
  EXPECT_FALSE(methods.contains("ground-truth@drift-model"));
  EXPECT_FALSE(methods.contains("constant=0.5@drift-model"));
  // the drift moved the frames: the maps differ from those on the true pose
  EXPECT_NE(methods.at("em@drift-model").at("frames").at("mean_error"),
            methods.at("em").at("frames").at("mean_error"));
  // the truth is known wherever a mapper is scored (it is computed on the cells any frame set
  // observed): FSGP-BGK knows every cell its frames observed, on the true frames' cells and on
  // those only the drifted frames observed
  const nlohmann::json& drifted = methods.at("fsgp-bgk@drift-model").at("frames");
  EXPECT_NE(drifted.at("observed_cells"), methods.at("fsgp-bgk").at("frames").at("observed_cells"));
  EXPECT_EQ(drifted.at("compared_cells"), drifted.at("observed_cells"));
  EXPECT_THAT(ReadFile(root_ / "eval" / "results.md"),
              HasSubstr("## The mappers on another pose source"));
  const std::string csv = ReadFile(root_ / "eval" / "pose_sources.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "method,pose_source,flat_error_true,flat_error,flat_auroc_true,flat_auroc");
  // the header, then fsgp-bgk and em on each source
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);

  // without drift the estimate is the truth: the same maps, number for number
  const CommandResult still = RunTrav(
      "eval --out " + (root_ / "still").string() +
      " --terrains flat --scenes 1 --seed 5 --frames 6 --jobs 1 --route-length 6 --no-ablation "
      "--methods em --pose-sources drift-model --set localization.translation_drift=0 --set "
      "localization.z_drift=0 --set localization.yaw_drift=0");
  ASSERT_EQ(still.exit_code, 0) << still.output;
  const nlohmann::json same = ReadJson(root_ / "still" / "scenes" / "flat-5.json").at("methods");
  EXPECT_EQ(same.at("em@drift-model").at("frames").at("mean_error"),
            same.at("em").at("frames").at("mean_error"));

  EXPECT_EQ(RunTrav("eval --out " + (root_ / "bad").string() + " --pose-sources true").exit_code,
            2);
  EXPECT_EQ(RunTrav("eval --out " + (root_ / "bad").string() + " --pose-sources dead-reckoning")
                .exit_code,
            2);
  EXPECT_FALSE(fs::exists(root_ / "bad"));
}

// Walls along both axes through the centre: every route (through the centre) is cut.
TEST_F(EvaluationTest, ASceneWithoutARouteIsRecordedAsNoRoute) {
  const CommandResult run = RunTrav(
      "eval --out " + (root_ / "eval").string() +
      " --terrains flat --scenes 1 --seed 1 --no-ablation --methods em --set "
      "'terrain.boxes=[{name: x, centre: [0, 0], half_extents: [25, 0.2], height: 2}, {name: y, "
      "centre: [0, 0], half_extents: [0.2, 25], height: 2}]'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json scene = ReadJson(root_ / "eval" / "scenes" / "flat-1.json");
  EXPECT_EQ(scene.at("drive").at("outcome"), "no_route");
  EXPECT_EQ(scene.at("route").at("draws"), 48);  // 16 headings at each of three lengths
  EXPECT_TRUE(scene.at("methods").empty());
  EXPECT_THAT(ReadFile(root_ / "eval" / "results.md"), HasSubstr("no_route 1 (flat-1)"));
}

TEST_F(EvaluationTest, ResumesWithoutRedoingFinishedScenes) {
  ASSERT_EQ(RunTrav(TinyEval()).exit_code, 0);
  const fs::path out = root_ / "eval";
  // an interrupted run: one scene not finished, a half-written record, no report
  fs::remove(out / "scenes/flat-6.json");
  fs::remove(out / "results.json");
  std::ofstream(out / "scenes/flat-6.json.partial-99999") << "{\"half\":";
  struct stat before {};
  ASSERT_EQ(stat((out / "scenes/flat-5.json").c_str(), &before), 0);
  const std::string finished_text = [&] {
    std::ifstream file(out / "scenes/flat-5.json");
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
  }();

  const CommandResult resumed = RunTrav(TinyEval());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("1 of 2 scenes already finished"));
  EXPECT_THAT(resumed.output, HasSubstr("scene flat-6 finished"));
  EXPECT_THAT(resumed.output, ::testing::Not(HasSubstr("scene flat-5 finished")));
  struct stat after {};
  ASSERT_EQ(stat((out / "scenes/flat-5.json").c_str(), &after), 0);
  EXPECT_EQ(after.st_ino, before.st_ino);
  EXPECT_EQ(after.st_mtim.tv_nsec, before.st_mtim.tv_nsec);
  EXPECT_EQ(after.st_mtim.tv_sec, before.st_mtim.tv_sec);
  std::ifstream file(out / "scenes/flat-5.json");
  std::stringstream text;
  text << file.rdbuf();
  EXPECT_EQ(text.str(), finished_text);
  EXPECT_TRUE(fs::is_regular_file(out / "scenes/flat-6.json"));
  EXPECT_FALSE(fs::exists(out / "scenes/flat-6.json.partial-99999"));
  EXPECT_EQ(ReadJson(out / "results.json").size(), 6u);

  // the same folder with other options is refused
  const CommandResult other = RunTrav(TinyEval() + " --route-length 10");
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_THAT(other.output, HasSubstr("options.json"));
}

// A scene record that cannot be read (cut short, edited, or written by another version) is never
// silently dropped or overwritten: collect reports it, and a resumed run keeps it aside.
TEST_F(EvaluationTest, AnUnreadableSceneRecordIsReportedAndKept) {
  ASSERT_EQ(RunTrav(TinyEval()).exit_code, 0);
  const fs::path out = root_ / "eval";
  const std::string broken = "{\"terrain\": \"flat\", \"methods\": 3}\n";
  std::ofstream(out / "scenes/flat-6.json") << broken;

  const CommandResult collected = RunTrav("eval --collect " + out.string());
  EXPECT_THAT(collected.output, HasSubstr("flat-6.json is not a scene record this trav can read"));
  EXPECT_THAT(ReadFile(out / "results.md"), HasSubstr("| flat-6 | unreadable record |"));
  EXPECT_EQ(ReadFile(out / "scenes/flat-6.json"), broken);

  const CommandResult resumed = RunTrav(TinyEval());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("scene flat-6 finished"));
  EXPECT_EQ(ReadFile(out / "scenes/flat-6.json.unreadable"), broken);
  EXPECT_EQ(ReadJson(out / "scenes/flat-6.json").at("terrain"), "flat");
  EXPECT_THAT(ReadFile(out / "results.md"), ::testing::Not(HasSubstr("unreadable record")));
}

TEST_F(EvaluationTest, RecordsAFailedSceneAndReportsTheOthers) {
  // a time limit no scene can meet: every scene is killed and recorded, the run exits 1
  const CommandResult run = RunTrav("eval --out " + (root_ / "eval").string() +
                                    " --terrains flat --scenes 1 --frames 6 --methods em"
                                    " --no-ablation --time-limit 0.01");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_THAT(run.output, HasSubstr("1 failed"));
  const nlohmann::json failure = ReadJson(root_ / "eval/failed/flat-1.json");
  EXPECT_EQ(failure.at("end"), "timed_out");
  std::ifstream md_file(root_ / "eval/results.md");
  std::stringstream md;
  md << md_file.rdbuf();
  EXPECT_THAT(md.str(), HasSubstr("| flat-1 | timed_out |"));
  EXPECT_EQ(ReadJson(root_ / "eval/results.json").size(), 0u);
}

TEST_F(EvaluationTest, BadArgumentsExitWithTwoAndWriteNothing) {
  const std::string out = " --out " + (root_ / "eval").string();
  const std::pair<std::string, std::string> cases[] = {
      {"--scenes 0", "--scenes"},
      {"--methods fsgp,magic", "magic"},
      {"--methods constant=2", "constant=2"},
      {"--terrains hilly,moon", "moon"},
      {"--set mapping.nonsense=1", "mapping.nonsense"},
      {"--route-length -3", "--route-length"},
      {"--jobs 0", "--jobs"},
      {"--inducing 5", "--inducing"},
      {"--frames x", "--frames"},
      {"--truth magic", "--truth"},
  };
  for (const auto& [arguments, named] : cases) {
    const CommandResult run = RunTrav("eval" + out + " " + arguments);
    EXPECT_EQ(run.exit_code, 2) << arguments << ": " << run.output;
    EXPECT_THAT(run.output, HasSubstr(named)) << arguments;
    EXPECT_FALSE(fs::exists(root_ / "eval")) << arguments;
  }
}

}  // namespace
}  // namespace trav::scenarios
