// SPDX-License-Identifier: MIT
// The CLI's report layer (cli/report.h): its JSON parses whatever the
// numbers and strings hold (non-finite numbers as null, strings escaped,
// bytes that are not UTF-8 replaced) and its tables have the documented shape.
#include <gtest/gtest.h>

#include <limits>

#include "report.h"

namespace simdbvh::cli {
namespace {

TEST(ReportJson, NonFiniteNumbersAreNull) {
    const double inf = std::numeric_limits<double>::infinity();
    const Json doc{{"inf", inf},
                   {"minus_inf", -inf},
                   {"nan", std::numeric_limits<double>::quiet_NaN()},
                   {"x", 1.5},
                   {"list", {inf, 2.0}}};
    const std::string text = json_text(doc);
    for (const char* bad : {": inf", ": -inf", ": nan", ": -nan", "Infinity", "NaN"})
        EXPECT_EQ(text.find(bad), std::string::npos) << bad << " in " << text;
    const Json back = Json::parse(text);  // throws (fails the test) on invalid JSON
    EXPECT_TRUE(back["inf"].is_null());
    EXPECT_TRUE(back["minus_inf"].is_null());
    EXPECT_TRUE(back["nan"].is_null());
    EXPECT_EQ(back["x"].get<double>(), 1.5);
    EXPECT_TRUE(back["list"][0].is_null());
    EXPECT_EQ(back["list"][1].get<double>(), 2.0);
}

TEST(ReportJson, StringsAreEscaped) {
    const std::string nasty =
        "a\"b\\c\nd\te\x01"
        "f'g";
    const std::string text = json_text(Json{{"s", nasty}});
    EXPECT_NE(text.find(R"(a\"b\\c\nd\te\u0001f'g)"), std::string::npos) << text;
    EXPECT_EQ(Json::parse(text)["s"].get<std::string>(), nasty);
}

TEST(ReportJson, BytesThatAreNotUtf8AreReplaced) {
    const std::string text = json_text(Json{{"path", std::string("x\xff"
                                                                 "y")}});
    EXPECT_EQ(Json::parse(text)["path"].get<std::string>(), "x\xEF\xBF\xBDy");  // U+FFFD
}

TEST(ReportTable, MarkdownAndText) {
    Table t({"method", "Mrays/s"});
    t.row({"bvh2", "1.5"}).row({"bvh16/avx512", "12"});
    EXPECT_EQ(t.markdown(), "| method | Mrays/s |\n|---|---:|\n| bvh2 | 1.5 |\n| bvh16/avx512 | 12 |\n");
    EXPECT_EQ(t.text(),
              "method        Mrays/s\n"
              "bvh2              1.5\n"
              "bvh16/avx512       12\n");
}

TEST(ReportTable, ShortRowsArePadded) {
    Table t({"a", "b", "c"}, "lll");
    t.row({"x"});
    EXPECT_EQ(t.markdown(), "| a | b | c |\n|---|---|---|\n| x |  |  |\n");
}

TEST(ReportCommandLine, KeepsArgumentsAsTyped) {
    EXPECT_EQ(command_line("bench", {"--scene", "a\"b"}), "simdbvh bench --scene a\"b");
}

}  // namespace
}  // namespace simdbvh::cli
