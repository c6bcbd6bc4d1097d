#include "common/text.h"

#include <gtest/gtest.h>

namespace trav::common {
namespace {

TEST(TextTest, MarkupCharactersAreEscapedAndNothingElse) {
  EXPECT_EQ(EscapeMarkup(R"(a<b>&"c" 'd' /é)"), "a&lt;b&gt;&amp;&quot;c&quot; &#39;d&#39; /é");
  EXPECT_EQ(EscapeMarkup(""), "");
}

TEST(TextTest, NumbersAreFormattedAsPrintfDoes) {
  EXPECT_EQ(FormatNumber("%.3g", 1.23456), "1.23");
  EXPECT_EQ(FormatNumber("%.0f %%", 42.4), "42 %");
}

}  // namespace
}  // namespace trav::common
