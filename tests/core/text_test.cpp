// Text in any encoding: UTF-8 kept, anything else read as Latin-1; a byte-order mark dropped.
#include <gtest/gtest.h>

#include "sinew/core/text.h"

namespace sinew {
namespace {

TEST(TextTest, ValidUtf8IsKeptAsItIs) {
  EXPECT_TRUE(
      isValidUtf8("H\xC3\xBC"
                  "fte"));                                   // Hüfte
  EXPECT_TRUE(isValidUtf8("\xE6\xBC\xA2\xF0\x9F\x98\x80"));  // 漢 and an emoji
  EXPECT_EQ(toUtf8("H\xC3\xBC"
                   "fte"),
            "H\xC3\xBC"
            "fte");
  EXPECT_EQ(toUtf8("Hips"), "Hips");
}

TEST(TextTest, InvalidUtf8IsReadAsLatin1) {
  EXPECT_FALSE(
      isValidUtf8("H\xFC"
                  "fte"));                        // Latin-1 ü
  EXPECT_FALSE(isValidUtf8("\xC0\xAF"));          // overlong '/'
  EXPECT_FALSE(isValidUtf8("\xED\xA0\x80"));      // a surrogate
  EXPECT_FALSE(isValidUtf8("\xF4\x90\x80\x80"));  // past U+10FFFF
  EXPECT_FALSE(isValidUtf8("\xE6\xBC"));          // cut short
  EXPECT_EQ(toUtf8("H\xFC"
                   "fte"),
            "H\xC3\xBC"
            "fte");
  EXPECT_EQ(toUtf8("\xE9t\xE9"), "\xC3\xA9t\xC3\xA9");  // été
  EXPECT_TRUE(isValidUtf8(toUtf8("\x80\xFF\xC0\xAF")));
}

TEST(TextTest, ByteOrderMarkIsDroppedAndControlCharactersFound) {
  EXPECT_EQ(withoutBom("\xEF\xBB\xBFHIERARCHY"), "HIERARCHY");
  EXPECT_EQ(withoutBom("HIERARCHY"), "HIERARCHY");
  EXPECT_EQ(textAsUtf8("\xEF\xBB\xBF"
                       "H\xFC"
                       "fte"),
            "H\xC3\xBC"
            "fte");
  EXPECT_EQ(firstControlCharacter("Hips"), -1);
  EXPECT_EQ(firstControlCharacter(std::string("Sp\0ine", 6)), 0);
  EXPECT_EQ(firstControlCharacter("a\x7F"), 127);
}

}  // namespace
}  // namespace sinew
