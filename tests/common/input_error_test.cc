#include "common/input_error.h"

#include <gtest/gtest.h>

namespace trav::common {
namespace {

TEST(InputErrorTest, AKeyRelativeToItsStructGetsTheSectionAndTheFileFromOutside) {
  const InputError relative("", "rate", "value 0 must be > 0");
  EXPECT_STREQ(relative.what(), "rate: value 0 must be > 0");
  const InputError placed = relative.AtKey("lidar").InFile("s.yaml");
  EXPECT_STREQ(placed.what(), "s.yaml: lidar.rate: value 0 must be > 0");
  EXPECT_EQ(placed.file(), "s.yaml");
  EXPECT_EQ(placed.key_path(), "lidar.rate");
}

TEST(InputErrorTest, ASequenceItemJoinsWithoutADotAndAnEmptyKeyTakesThePrefix) {
  EXPECT_STREQ(InputError("", "[2].name", "is used twice").AtKey("movers").what(),
               "movers[2].name: is used twice");
  EXPECT_STREQ(InputError("r.xml", "", "does not load").AtKey("robot.model").what(),
               "r.xml: robot.model: does not load");
  EXPECT_STREQ(InputError("", "x", "bad").AtKey("").what(), "x: bad");
}

TEST(InputErrorTest, AFileNamedByTheErrorItselfIsKept) {
  EXPECT_STREQ(InputError("table.csv", "", "has no rows").InFile("s.yaml").what(),
               "table.csv: has no rows");
}

TEST(InputErrorTest, ValidateAtPrefixesEveryInputErrorAndPassesOthersThrough) {
  try {
    ValidateAt("mapping.gp", [] { RequireValue(false, "noise_std", -1.0, "must be > 0"); });
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "mapping.gp.noise_std: value -1.000000 must be > 0");
  }
  EXPECT_THROW(ValidateAt("x", [] { throw std::logic_error("bug"); }), std::logic_error);
  EXPECT_NO_THROW(ValidateAt("x", [] {}));
}

}  // namespace
}  // namespace trav::common
