#include "f2c/util/text.h"

#include <gtest/gtest.h>

#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {

TEST(ParseDouble, AcceptsOnlyWholeFiniteNumbers) {
  double v = 0;
  EXPECT_TRUE(ParseDouble("1.5e-3", &v));
  EXPECT_DOUBLE_EQ(v, 1.5e-3);
  EXPECT_TRUE(ParseDouble("-2", &v));
  EXPECT_DOUBLE_EQ(v, -2.0);
  EXPECT_FALSE(ParseDouble("1.0x", &v));
  EXPECT_FALSE(ParseDouble("nan", &v));
  EXPECT_FALSE(ParseDouble("inf", &v));
  EXPECT_FALSE(ParseDouble("", &v));
}

TEST(SplitWhitespace, TabsAndRepeatedSpaces) {
  const auto tokens = SplitWhitespace(" a\t b  c ");
  ASSERT_EQ(tokens.size(), 3u);
  EXPECT_EQ(tokens[0], "a");
  EXPECT_EQ(tokens[2], "c");
}

TEST(ReadDataLines, SkipsCommentsAndKeepsLineNumbers) {
  const auto path = std::filesystem::temp_directory_path() / "f2c_text_test.txt";
  WriteFileAtomic(path, "# header\n\n1 2\r\n  # indented comment\n3 4\n");
  const auto lines = ReadDataLines(path);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].number, 3);
  EXPECT_EQ(lines[0].text, "1 2");
  EXPECT_EQ(lines[1].number, 5);
  // Lines of only carriage returns, vertical tabs or form feeds hold no token: skipped too
  // (a .conf line like this once indexed an empty token list; found by fuzz_trajectory).
  WriteFileAtomic(path, "1\n\r\r\r\n\v\f \n2\n");
  const auto blank = ReadDataLines(path);
  ASSERT_EQ(blank.size(), 2u);
  for (const TextLine& line : blank) EXPECT_FALSE(SplitWhitespace(line.text).empty());
}

TEST(ParseDoublesOrThrow, NamesFileLineAndToken) {
  try {
    ParseDoublesOrThrow({"x", "1", "zz"}, 1, "f.txt", 7, "3 numbers");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "f.txt:7: 'zz' is not a finite number; expected 3 numbers");
  }
}

}  // namespace
}  // namespace f2c
