// printableText: names read from files reach the terminal with every control byte escaped.
#include "ngi/printable_text.h"

#include <gtest/gtest.h>

#include <string>

namespace {

TEST(PrintableText, EscapesControlBytesAndMalformedUtf8)
{
    EXPECT_EQ(ngi::printableText("bunny.obj"), "bunny.obj");
    EXPECT_EQ(ngi::printableText("caf\xc3\xa9 \xe6\x97\xa5.obj"), "caf\xc3\xa9 \xe6\x97\xa5.obj");  // UTF-8 passes
    EXPECT_EQ(ngi::printableText("evil\x1b]0;owned\x07\x1b[2J\r\n.obj"),
              "evil\\x1b]0;owned\\x07\\x1b[2J\\x0d\\x0a.obj");
    EXPECT_EQ(ngi::printableText(std::string("a\0b\x7f", 4)), "a\\x00b\\x7f");
    EXPECT_EQ(ngi::printableText("\x9b"
                                 "2J"),
              "\\x9b2J");  // an 8-bit CSI
    EXPECT_EQ(ngi::printableText("\xc2\x9b"
                                 "2J"),
              "\\xc2\\x9b2J");  // CSI as UTF-8 (a C1 control)
    EXPECT_EQ(ngi::printableText("\xc0\xaf \xed\xa0\x80 \xf4\x90\x80\x80 \xe6\x97"),
              "\\xc0\\xaf \\xed\\xa0\\x80 \\xf4\\x90\\x80\\x80 \\xe6\\x97");  // overlong, surrogate, > U+10FFFF, cut
    EXPECT_EQ(ngi::printableText("a\\x1b"), "a\\\\x1b");                      // a backslash cannot fake an escape
}

}  // namespace
