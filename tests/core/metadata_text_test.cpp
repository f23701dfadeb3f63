// indentedMetadata: an asset's META laid out like a pretty JSON dump, linear in its size even
// for hostile nesting (a pretty dump grows with the square of the depth).
#include "ngi/metadata_text.h"

#include <gtest/gtest.h>

#include <string>

namespace {

TEST(MetadataText, IndentsLikeAPrettyJsonDump)
{
    EXPECT_EQ(ngi::indentedMetadata(R"({"a":1, "b":[1,2],"c":{},"d":"x,{y}\"z", "e":[ ]})"),
              "{\n"
              "  \"a\": 1,\n"
              "  \"b\": [\n"
              "    1,\n"
              "    2\n"
              "  ],\n"
              "  \"c\": {},\n"
              "  \"d\": \"x,{y}\\\"z\",\n"
              "  \"e\": []\n"
              "}");
    EXPECT_EQ(ngi::indentedMetadata(""), "");
    EXPECT_EQ(ngi::indentedMetadata("not json"), "notjson");  // laid out, never an error
}

TEST(MetadataText, DeepNestingIsBoundedInDepthAndSize)
{
    // 100 KB of nesting, 50,000 levels deep: a pretty dump would be ~2.5 GB.
    const size_t depth = 50000;
    const std::string deep = std::string(depth, '[') + "1" + std::string(depth, ']');
    const std::string all = ngi::indentedMetadata(deep, 16, std::string::npos);
    EXPECT_LT(all.size(), deep.size() * (2 * 16 + 4));  // indentation capped at 16 levels
    EXPECT_EQ(all.substr(0, 4), "[\n  ");
    EXPECT_EQ(all.back(), ']');

    const std::string shown = ngi::indentedMetadata(deep);  // the default bound, 64 KiB
    EXPECT_LT(shown.size(), (size_t(64) << 10) + 200);
    EXPECT_NE(shown.find("more bytes of metadata not shown"), std::string::npos);
}

}  // namespace
