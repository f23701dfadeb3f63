// ngi offline eval: a small SVG line-plot writer for the report's figures (rate-distortion
// curves, error against LoD). No plotting package: the report must build from Debian's
// C++ toolchain alone, and a figure is a few hundred bytes of XML we can test.
//
// A plot has a title, axis labels (which state the units), optional log10 axes, a legend
// and one polyline with markers per series. Points whose coordinate is not finite, or not
// positive on a log axis, are left out (and counted in SvgPlotResult::droppedPoints).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace ngi {

struct PlotPoint {
    double x = 0.0;
    double y = 0.0;
};

struct PlotSeries {
    std::string name;               // legend entry
    std::vector<PlotPoint> points;  // drawn in this order
    std::string colour;             // SVG colour; "" = the next of a fixed palette
    bool dashed = false;
};

struct SvgPlotOptions {
    std::string title;
    std::string xLabel;   // with unit, e.g. "bytes on disk (log)"
    std::string yLabel;   // with unit, e.g. "CD x1e-4 (log)"
    std::string caption;  // small text under the plot (e.g. the command that made it)
    bool logX = false;
    bool logY = false;
    int width = 720;  // pixels
    int height = 480;
};

struct SvgPlotResult {
    std::string svg;  // a complete SVG document
    size_t drawnPoints = 0;
    size_t droppedPoints = 0;  // not finite, or <= 0 on a log axis
};

// Lays out and writes the plot. Axis ranges cover every drawn point (padded; on log axes
// extended to whole decades when the range spans less than one). Ticks are decades (1, 10,
// 100 ...) on log axes and 1-2-5 steps on linear axes; every coordinate written is finite.
// A plot with no drawable point is still a valid SVG saying "no data". Text is XML-escaped.
// Never throws for data; throws ngi::Error if width or height < 100.
SvgPlotResult makeSvgLinePlot(const std::vector<PlotSeries>& series, const SvgPlotOptions& options);

// Escapes &, <, >, " and ' for XML text and attribute values.
std::string xmlEscape(const std::string& text);

}  // namespace ngi
