// The report's SVG writer: well-formed XML (balanced tags), finite coordinates, log axes whose
// tick positions grow with their values, points that cannot be drawn left out, text escaped.
#include "ngi/error.h"
#include "ngi/eval/svg_plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <regex>
#include <string>
#include <vector>

namespace {

// Checks that every element is closed in order (a minimal XML well-formedness check: tags,
// self-closing tags, the prolog, and no stray '<' or '&' in text).
::testing::AssertionResult wellFormed(const std::string& svg)
{
    std::vector<std::string> stack;
    size_t i = 0;
    while (i < svg.size()) {
        const size_t open = svg.find('<', i);
        const std::string text = svg.substr(i, open == std::string::npos ? std::string::npos : open - i);
        for (size_t a = text.find('&'); a != std::string::npos; a = text.find('&', a + 1))
            if (!std::regex_search(text.substr(a), std::regex("^&(amp|lt|gt|quot|apos);")))
                return ::testing::AssertionFailure() << "bare '&' in text: " << text;
        if (open == std::string::npos) break;
        const size_t close = svg.find('>', open);
        if (close == std::string::npos) return ::testing::AssertionFailure() << "unterminated tag at " << open;
        const std::string tag = svg.substr(open + 1, close - open - 1);
        if (tag.find('<') != std::string::npos) return ::testing::AssertionFailure() << "'<' inside a tag: " << tag;
        i = close + 1;
        if (tag.starts_with("?")) continue;
        if (tag.starts_with("/")) {
            const std::string name = tag.substr(1);
            if (stack.empty() || stack.back() != name)
                return ::testing::AssertionFailure() << "unbalanced </" << name << ">";
            stack.pop_back();
            continue;
        }
        const std::string name = tag.substr(0, tag.find_first_of(" \n/"));
        if (!tag.ends_with("/")) stack.push_back(name);
    }
    if (!stack.empty()) return ::testing::AssertionFailure() << "unclosed <" << stack.back() << ">";
    return ::testing::AssertionSuccess();
}

std::vector<double> numericAttributes(const std::string& svg)
{
    std::vector<double> values;
    const std::regex attribute(R"re(\b(x|y|x1|x2|y1|y2|cx|cy|width|height)="([^"]*)")re");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), attribute); it != std::sregex_iterator(); ++it)
        values.push_back(std::stod((*it)[2].str()));
    const std::regex points(R"re(points="([^"]*)")re");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), points); it != std::sregex_iterator(); ++it) {
        std::string list = (*it)[1].str();
        for (char& c : list)
            if (c == ',') c = ' ';
        std::istringstream in(list);
        double v;
        while (in >> v) values.push_back(v);
    }
    return values;
}

std::vector<ngi::PlotSeries> rateDistortion()
{
    ngi::PlotSeries a{"ngi <no SR> & co", {{3900, 12.6}, {6000, 1.86}, {13000, 0.46}, {40000, 0.1}}};
    ngi::PlotSeries b{"peer",
                      {{3800, 0.8},
                       {6100, 0.3},
                       {13000, 0.03},
                       {0, 1.0},
                       {5000, -1.0},
                       {std::numeric_limits<double>::quiet_NaN(), 1.0}}};
    return {a, b};
}

TEST(SvgPlot, LogLogPlotIsWellFormedWithFiniteCoordinates)
{
    ngi::SvgPlotOptions o;
    o.title = "fandisk: CD <against> bytes";
    o.xLabel = "bytes on disk (log)";
    o.yLabel = "CD x1e-4 (log)";
    o.caption = "made by: ngi-eval report --meshes a.off,b.off --out 'dir' --resolution 64 and a long tail of "
                "options that has to wrap over several caption lines to stay inside the picture";
    o.logX = o.logY = true;
    const ngi::SvgPlotResult r = ngi::makeSvgLinePlot(rateDistortion(), o);
    EXPECT_TRUE(wellFormed(r.svg)) << r.svg;
    EXPECT_EQ(r.drawnPoints, 7u);
    EXPECT_EQ(r.droppedPoints, 3u);  // x = 0 and y < 0 on log axes, NaN
    const std::vector<double> values = numericAttributes(r.svg);
    ASSERT_GT(values.size(), 20u);
    for (double v : values) {
        EXPECT_TRUE(std::isfinite(v));
        EXPECT_GE(v, -1.0);
        EXPECT_LE(v, 721.0);
    }
    EXPECT_NE(r.svg.find("&lt;no SR&gt; &amp; co"), std::string::npos);
    EXPECT_NE(r.svg.find("CD x1e-4 (log)"), std::string::npos);
    EXPECT_NE(r.svg.find("made by: ngi-eval report"), std::string::npos);
}

TEST(SvgPlot, LogAxisTicksAreDecadesAtIncreasingPositions)
{
    ngi::SvgPlotOptions o;
    o.logX = o.logY = true;
    const std::string svg = ngi::makeSvgLinePlot(rateDistortion(), o).svg;
    // x tick labels sit at y = plot bottom + 16, text-anchor middle: "<text x=.. y=..
    // text-anchor="middle">LABEL</text>"; their x must grow with their value, by decades.
    const std::regex tick(R"re(<text x="([0-9.]+)" y="([0-9.]+)" text-anchor="middle">([^<]+)</text>)re");
    std::vector<std::pair<double, double>> xTicks;  // (value, position)
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), tick); it != std::sregex_iterator(); ++it) {
        const std::string label = (*it)[3].str();
        char* end = nullptr;
        const double value = std::strtod(label.c_str(), &end);
        if (end && *end == '\0') xTicks.emplace_back(value, std::stod((*it)[1].str()));
    }
    ASSERT_GE(xTicks.size(), 2u) << svg;
    for (size_t i = 1; i < xTicks.size(); ++i) {
        EXPECT_GT(xTicks[i].first, xTicks[i - 1].first);
        EXPECT_GT(xTicks[i].second, xTicks[i - 1].second);
        const double ratio = xTicks[i].first / xTicks[i - 1].first;
        EXPECT_NEAR(std::log10(ratio), std::round(std::log10(ratio)), 1e-9);  // whole decades
    }
    // Equal steps in log space are equal steps on screen.
    if (xTicks.size() >= 3) {
        EXPECT_NEAR(xTicks[1].second - xTicks[0].second, xTicks[2].second - xTicks[1].second, 0.02);
    }
}

TEST(SvgPlot, LinearAxesAndEmptyPlotsAreValid)
{
    ngi::SvgPlotOptions o;
    o.title = "LoD";
    const ngi::SvgPlotResult flat = ngi::makeSvgLinePlot({{"one value", {{1, 2}, {1, 2}}}}, o);
    EXPECT_TRUE(wellFormed(flat.svg));
    for (double v : numericAttributes(flat.svg)) EXPECT_TRUE(std::isfinite(v));

    o.logY = true;
    const ngi::SvgPlotResult empty = ngi::makeSvgLinePlot({{"nothing", {{1, 0}, {2, -3}}}}, o);
    EXPECT_TRUE(wellFormed(empty.svg));
    EXPECT_EQ(empty.drawnPoints, 0u);
    EXPECT_NE(empty.svg.find("no data"), std::string::npos);

    o.width = 50;
    EXPECT_THROW(ngi::makeSvgLinePlot({}, o), ngi::Error);
}

}  // namespace
