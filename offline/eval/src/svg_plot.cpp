// ngi offline eval: SVG line plots (see svg_plot.h). Plain string building: a viewBox in
// pixels, a plot area with margins for the tick labels, decade ticks on log axes and
// 1-2-5 ticks on linear axes.
#include "ngi/eval/svg_plot.h"

#include "ngi/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace ngi {

namespace {

const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};

std::string number(double v)
{
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.2f", v);
    return buffer;
}

// A tick label: compact, no trailing zeros ("0.001", "20", "1e+06").
std::string tickLabel(double v)
{
    char buffer[32];
    if (v != 0.0 && (std::fabs(v) >= 1e5 || std::fabs(v) < 1e-3))
        std::snprintf(buffer, sizeof buffer, "%.0e", v);
    else
        std::snprintf(buffer, sizeof buffer, "%.6g", v);
    return buffer;
}

struct Axis {
    bool log = false;
    double lo = 0.0, hi = 1.0;  // in axis space (log10 of the value on log axes)
    std::vector<double> ticks;  // values (not axis space)

    double toAxis(double v) const { return log ? std::log10(v) : v; }
    double fraction(double v) const { return (toAxis(v) - lo) / (hi - lo); }
};

Axis makeAxis(double minValue, double maxValue, bool log)
{
    Axis axis;
    axis.log = log;
    double lo = log ? std::log10(minValue) : minValue;
    double hi = log ? std::log10(maxValue) : maxValue;
    if (log) {
        lo = std::floor(lo);
        hi = std::ceil(hi);
        if (hi <= lo) hi = lo + 1.0;
        const int step = std::max(1, int(std::ceil((hi - lo) / 8.0)));
        for (double e = lo; e <= hi + 1e-9; e += step) axis.ticks.push_back(std::pow(10.0, e));
    } else {
        if (hi <= lo) {
            const double pad = lo == 0.0 ? 1.0 : std::fabs(lo) * 0.1;
            lo -= pad;
            hi += pad;
        }
        const double raw = (hi - lo) / 6.0;
        const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
        double step = magnitude;
        for (double m : {1.0, 2.0, 5.0, 10.0})
            if (m * magnitude >= raw) {
                step = m * magnitude;
                break;
            }
        lo = std::floor(lo / step) * step;
        hi = std::ceil(hi / step) * step;
        for (double t = lo; t <= hi + step * 1e-6; t += step)
            axis.ticks.push_back(std::fabs(t) < step * 1e-9 ? 0.0 : t);
    }
    axis.lo = lo;
    axis.hi = hi;
    return axis;
}

bool drawable(const PlotPoint& p, const SvgPlotOptions& o)
{
    return std::isfinite(p.x) && std::isfinite(p.y) && (!o.logX || p.x > 0.0) && (!o.logY || p.y > 0.0);
}

}  // namespace

std::string xmlEscape(const std::string& text)
{
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        default: out += c;
        }
    }
    return out;
}

SvgPlotResult makeSvgLinePlot(const std::vector<PlotSeries>& series, const SvgPlotOptions& o)
{
    if (o.width < 100 || o.height < 100) throw Error("svg plot: width and height must be at least 100 pixels");
    SvgPlotResult result;
    double minX = std::numeric_limits<double>::infinity(), maxX = -minX;
    double minY = minX, maxY = -minX;
    for (const PlotSeries& s : series)
        for (const PlotPoint& p : s.points) {
            if (!drawable(p, o)) {
                ++result.droppedPoints;
                continue;
            }
            ++result.drawnPoints;
            minX = std::min(minX, p.x);
            maxX = std::max(maxX, p.x);
            minY = std::min(minY, p.y);
            maxY = std::max(maxY, p.y);
        }

    // The caption is wrapped at spaces to the plot's width (about 6 pixels per character).
    std::vector<std::string> captionLines;
    {
        const size_t perLine = size_t(std::max(20, o.width / 6 - 4));
        std::string line;
        size_t start = 0;
        while (start < o.caption.size()) {
            size_t end = o.caption.find(' ', start);
            if (end == std::string::npos) end = o.caption.size();
            const std::string word = o.caption.substr(start, end - start);
            if (!line.empty() && line.size() + 1 + word.size() > perLine) {
                captionLines.push_back(line);
                line.clear();
            }
            line += (line.empty() ? "" : " ") + word;
            start = end + 1;
        }
        if (!line.empty()) captionLines.push_back(line);
    }
    const double left = 80, right = 190, top = 40, bottom = 60 + 13.0 * double(captionLines.size());
    const double plotW = o.width - left - right, plotH = o.height - top - bottom;
    std::string& svg = result.svg;
    svg += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(o.width) + "\" height=\"" +
        std::to_string(o.height) + "\" viewBox=\"0 0 " + std::to_string(o.width) + " " + std::to_string(o.height) +
        "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    svg += "<rect x=\"0\" y=\"0\" width=\"" + std::to_string(o.width) + "\" height=\"" + std::to_string(o.height) +
        "\" fill=\"white\"/>\n";
    svg += "<text x=\"" + number(o.width / 2.0) + "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" +
        xmlEscape(o.title) + "</text>\n";
    for (size_t i = 0; i < captionLines.size(); ++i)
        svg += "<text x=\"8\" y=\"" + number(o.height - 8.0 - 13.0 * double(captionLines.size() - 1 - i)) +
            "\" font-size=\"10\" fill=\"#555\">" + xmlEscape(captionLines[i]) + "</text>\n";
    svg += "<rect x=\"" + number(left) + "\" y=\"" + number(top) + "\" width=\"" + number(plotW) + "\" height=\"" +
        number(plotH) + "\" fill=\"none\" stroke=\"black\"/>\n";

    if (result.drawnPoints == 0) {
        svg += "<text x=\"" + number(left + plotW / 2) + "\" y=\"" + number(top + plotH / 2) +
            "\" text-anchor=\"middle\">no data</text>\n</svg>\n";
        return result;
    }

    const Axis ax = makeAxis(minX, maxX, o.logX);
    const Axis ay = makeAxis(minY, maxY, o.logY);
    auto px = [&](double x) { return left + ax.fraction(x) * plotW; };
    auto py = [&](double y) { return top + (1.0 - ay.fraction(y)) * plotH; };

    svg += "<g stroke=\"#ddd\">\n";
    for (double t : ax.ticks)
        svg += "<line x1=\"" + number(px(t)) + "\" y1=\"" + number(top) + "\" x2=\"" + number(px(t)) + "\" y2=\"" +
            number(top + plotH) + "\"/>\n";
    for (double t : ay.ticks)
        svg += "<line x1=\"" + number(left) + "\" y1=\"" + number(py(t)) + "\" x2=\"" + number(left + plotW) +
            "\" y2=\"" + number(py(t)) + "\"/>\n";
    svg += "</g>\n";
    for (double t : ax.ticks)
        svg += "<text x=\"" + number(px(t)) + "\" y=\"" + number(top + plotH + 16) + "\" text-anchor=\"middle\">" +
            xmlEscape(tickLabel(t)) + "</text>\n";
    for (double t : ay.ticks)
        svg += "<text x=\"" + number(left - 6) + "\" y=\"" + number(py(t) + 4) + "\" text-anchor=\"end\">" +
            xmlEscape(tickLabel(t)) + "</text>\n";
    svg += "<text x=\"" + number(left + plotW / 2) + "\" y=\"" + number(top + plotH + 36) +
        "\" text-anchor=\"middle\">" + xmlEscape(o.xLabel) + "</text>\n";
    svg += "<text x=\"16\" y=\"" + number(top + plotH / 2) + "\" text-anchor=\"middle\" transform=\"rotate(-90 16 " +
        number(top + plotH / 2) + ")\">" + xmlEscape(o.yLabel) + "</text>\n";

    size_t paletteIndex = 0;
    for (size_t i = 0; i < series.size(); ++i) {
        const PlotSeries& s = series[i];
        const std::string colour = s.colour.empty() ? kPalette[paletteIndex++ % std::size(kPalette)] : s.colour;
        std::string points;
        std::string markers;
        for (const PlotPoint& p : s.points) {
            if (!drawable(p, o)) continue;
            points += number(px(p.x)) + "," + number(py(p.y)) + " ";
            markers += "<circle cx=\"" + number(px(p.x)) + "\" cy=\"" + number(py(p.y)) + "\" r=\"3\"/>\n";
        }
        svg += "<g fill=\"" + colour + "\" stroke=\"" + colour + "\">\n";
        if (!points.empty()) {
            points.pop_back();
            svg += "<polyline fill=\"none\" stroke-width=\"1.8\"" +
                std::string(s.dashed ? " stroke-dasharray=\"6 4\"" : "") + " points=\"" + points + "\"/>\n";
        }
        svg += markers;
        const double ly = top + 14 + 20.0 * double(i);
        svg += "<line x1=\"" + number(left + plotW + 12) + "\" y1=\"" + number(ly) + "\" x2=\"" +
            number(left + plotW + 36) + "\" y2=\"" + number(ly) + "\" stroke-width=\"2\"" +
            std::string(s.dashed ? " stroke-dasharray=\"6 4\"" : "") + "/>\n";
        svg += "<text x=\"" + number(left + plotW + 42) + "\" y=\"" + number(ly + 4) +
            "\" stroke=\"none\" fill=\"black\">" + xmlEscape(s.name) + "</text>\n";
        svg += "</g>\n";
    }
    svg += "</svg>\n";
    return result;
}

}  // namespace ngi
