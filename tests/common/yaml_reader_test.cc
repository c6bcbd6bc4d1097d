#include "common/yaml_reader.h"

#include <array>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/enum_names.h"

namespace trav::common {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr char kDocument[] = R"(
speed: 1.5
count: 3
seed: 42
name: hilly
enabled: true
start: [1, 2, 0.5]
nested:
  size: [50, 40]
)";

TEST(YamlReaderTest, ReadsTypedValuesAndLeavesAbsentKeysAtDefault) {
  const YamlDocument document = YamlDocument::Parse(kDocument, "test.yaml");
  YamlReader dut = document.Root();
  double speed = 0.0;
  int count = 0;
  std::uint64_t seed = 0;
  std::string name;
  bool enabled = false;
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  double absent = 7.0;
  dut.Read("speed", &speed);
  dut.Read("count", &count);
  dut.Read("seed", &seed);
  dut.Read("name", &name);
  dut.Read("enabled", &enabled);
  dut.Read("start", &start);
  dut.Read("absent", &absent);
  YamlReader nested = dut.Map("nested");
  Eigen::Vector2d size = Eigen::Vector2d::Zero();
  nested.Read("size", &size);
  nested.Finish();
  dut.Finish();
  EXPECT_EQ(speed, 1.5);
  EXPECT_EQ(count, 3);
  EXPECT_EQ(seed, 42u);
  EXPECT_EQ(name, "hilly");
  EXPECT_TRUE(enabled);
  EXPECT_EQ(start, Eigen::Vector3d(1, 2, 0.5));
  EXPECT_EQ(size, Eigen::Vector2d(50, 40));
  EXPECT_EQ(absent, 7.0);
}

TEST(YamlReaderTest, UnknownKeyNamesSourceAndPath) {
  const YamlDocument document = YamlDocument::Parse("nested: {size: [1, 2], sise: 3}", "s.yaml");
  YamlReader root = document.Root();
  YamlReader nested = root.Map("nested");
  Eigen::Vector2d size;
  nested.Read("size", &size);
  EXPECT_THAT([&] { nested.Finish(); },
              ThrowsMessage<InputError>(HasSubstr("s.yaml: nested.sise: unknown key")));
}

TEST(YamlReaderTest, WrongTypeNamesKeyAndValue) {
  const YamlDocument document =
      YamlDocument::Parse("count: many\nstart: [1, x, 2]\nseed: -4", "s.yaml");
  YamlReader dut = document.Root();
  int count = 0;
  EXPECT_THAT(
      [&] { dut.Read("count", &count); },
      ThrowsMessage<InputError>(HasSubstr("s.yaml: count: expected an integer, got 'many'")));
  Eigen::Vector3d start;
  EXPECT_THAT([&] { dut.Read("start", &start); },
              ThrowsMessage<InputError>(HasSubstr("start: expected a sequence of 3 numbers")));
  std::uint64_t seed = 0;
  EXPECT_THAT(
      [&] { dut.Read("seed", &seed); },
      ThrowsMessage<InputError>(HasSubstr("seed: expected a non-negative integer, got '-4'")));
}

TEST(YamlReaderTest, CheckReportsTheValue) {
  const YamlDocument document = YamlDocument::Parse("resolution: -0.1", "s.yaml");
  YamlReader dut = document.Root();
  double resolution = 0.1;
  dut.Read("resolution", &resolution);
  EXPECT_THAT([&] { dut.Check("resolution", resolution > 0.0, "must be > 0"); },
              ThrowsMessage<InputError>(HasSubstr("s.yaml: resolution: value '-0.1' must be > 0")));
}

enum class Mode { kA, kB };
inline constexpr std::array<EnumName<Mode>, 2> kModeNames{{{Mode::kA, "a"}, {Mode::kB, "b"}}};
constexpr const auto& EnumNames(Mode) { return kModeNames; }

TEST(YamlReaderTest, EnumReadsNamesOfItsTable) {
  const YamlDocument document = YamlDocument::Parse("mode: b", "s.yaml");
  YamlReader dut = document.Root();
  Mode mode = Mode::kA;
  dut.ReadEnum("mode", &mode);
  EXPECT_EQ(mode, Mode::kB);
  EXPECT_STREQ(NameOf(Mode::kB), "b");
  EXPECT_EQ(EnumFromName<Mode>("a"), Mode::kA);
  EXPECT_EQ(EnumFromName<Mode>("c"), std::nullopt);
  EXPECT_EQ(EnumNameList<Mode>(), "a, b");
}

TEST(YamlReaderTest, EnumRejectsUnknownNamesListingValidOnes) {
  const YamlDocument document = YamlDocument::Parse("mode: c", "s.yaml");
  YamlReader dut = document.Root();
  Mode mode = Mode::kA;
  EXPECT_THAT(
      [&] { dut.ReadEnum("mode", &mode); },
      ThrowsMessage<InputError>(HasSubstr("mode: unknown value 'c' (expected one of: a, b)")));
}

TEST(YamlDocumentTest, SetOverridesAndCreatesNestedKeys) {
  YamlDocument dut = YamlDocument::Parse(kDocument, "test.yaml");
  dut.Set("nested.size", "[3, 4]");
  dut.Set("speed", "2.5");
  dut.Set("new.deep.key", "true");
  YamlReader root = dut.Root();
  double speed = 0.0;
  root.Read("speed", &speed);
  Eigen::Vector2d size;
  root.Map("nested").Read("size", &size);
  bool key = false;
  root.Map("new").Map("deep").Read("key", &key);
  EXPECT_EQ(speed, 2.5);
  EXPECT_EQ(size, Eigen::Vector2d(3, 4));
  EXPECT_TRUE(key);
  dut.SetString("name", "it's: [not yaml]");
  std::string name;
  dut.Root().Read("name", &name);
  EXPECT_EQ(name, "it's: [not yaml]");
  EXPECT_THAT([&] { dut.Set("speed.x", "1"); },
              ThrowsMessage<InputError>(HasSubstr("'speed' is not a map")));
}

TEST(YamlDocumentTest, SetReachesIntoSequencesByIndex) {
  YamlDocument dut = YamlDocument::Parse(
      "weights: [1, 2, 3]\nlegs: [{v: 1.0, duration: 2}, {v: 0.5, duration: 1}]\n", "test.yaml");
  dut.Set("weights[2]", "30");
  dut.Set("legs[1].v", "0.75");
  Eigen::Vector3d weights;
  dut.Root().Read("weights", &weights);
  EXPECT_EQ(weights, Eigen::Vector3d(1, 2, 30));
  double v = 0.0;
  dut.Root().MapSequence("legs")[1].Read("v", &v);
  EXPECT_EQ(v, 0.75);
  EXPECT_EQ(dut.Find("weights[2]"), "30");
  EXPECT_EQ(dut.Find("legs[1].v"), "0.75");
  EXPECT_EQ(dut.Find("weights"), "[1, 2, 30]");
  EXPECT_FALSE(dut.Find("legs[2].v").has_value());
  EXPECT_FALSE(dut.Find("nothing.here").has_value());
  EXPECT_THAT([&] { dut.Set("weights[3]", "1"); },
              ThrowsMessage<InputError>(HasSubstr("'weights' has no item 3")));
  EXPECT_THAT([&] { dut.Set("missing[0]", "1"); },
              ThrowsMessage<InputError>(HasSubstr("'missing' has no item 0")));
  EXPECT_THAT([&] { dut.Set("weights[x]", "1"); },
              ThrowsMessage<InputError>(HasSubstr("expected name[index]")));
  EXPECT_THAT([&] { dut.Set("weights[0].a", "1"); },
              ThrowsMessage<InputError>(HasSubstr("items are not maps")));
}

TEST(YamlDocumentTest, MissingFileAndBadSyntaxAreInputErrors) {
  EXPECT_THAT([] { YamlDocument::Load("/nonexistent/scenario.yaml"); },
              ThrowsMessage<InputError>(HasSubstr(
                  "/nonexistent/scenario.yaml: cannot open YAML file: No such file or directory")));
  EXPECT_THAT([] { YamlDocument::Parse("a: [1, 2", "bad.yaml"); },
              ThrowsMessage<InputError>(HasSubstr("bad.yaml: invalid YAML")));
  EXPECT_THAT(
      [] { YamlDocument::Parse("- 1\n- 2", "list.yaml"); },
      ThrowsMessage<InputError>(HasSubstr("list.yaml: expected a YAML map at the top level")));
}

}  // namespace
}  // namespace trav::common
