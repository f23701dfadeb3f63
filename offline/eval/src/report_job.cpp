// ngi offline eval, report internals: one mesh's measurement and asset paths (report_job.h).
#include "report_job.h"

#include "ngi/eval/surface_distance.h"

namespace ngi::report_detail {

namespace fs = std::filesystem;

std::string oneLine(std::string text)
{
    for (char& c : text)
        if (c == '\n' || c == '\r' || c == '|') c = ' ';
    return text;
}

Measured MeshContext::measure(const TriangleMesh& candidate, const std::string& step)
{
    Measured m;
    m.triangles = candidate.triangles.size();
    try {
        SurfaceDistanceOptions o;
        o.sampleCount = options.sampleCount;
        o.threadCount = distanceThreads;
        const SurfaceDistance d = surfaceDistance(input, candidate, o);
        m.cd = d.chamfer * kChamferReportScale;
        m.hd = d.hausdorff * kHausdorffReportScale;
        m.ok = finite(m.cd) && finite(m.hd);
        if (!m.ok) m.failure = "failed: non-finite distance";
    } catch (const std::exception& e) {
        m.failure = "failed: " + oneLine(e.what());
    }
    progress.advance(1.0, report.name + ": " + step);
    return m;
}

fs::path MeshContext::assetPath(const std::string& method, const std::string& suffix) const
{
    return options.outDir / "assets" / (report.name + "." + method + "." + suffix);
}

}  // namespace ngi::report_detail
