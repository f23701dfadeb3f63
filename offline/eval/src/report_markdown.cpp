// ngi offline eval, the report's page: Markdown tables (paper Tables 1 and 4, peers at equal
// bytes and at equal triangle count), the SVG plots and the contact-sheet captions, from the
// rows report.cpp measured.
#include "report_data.h"

#include "ngi/asset.h"
#include "ngi/stored_level.h"
#include "ngi/eval/svg_plot.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>

namespace ngi::report_detail {

namespace fs = std::filesystem;

namespace {

std::string fixed(double v, int digits = 4)
{
    if (!finite(v)) return "n/a";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
    return buffer;
}

// A CD or HD value: 4 decimals, or 3 significant digits below 0.01 (so small errors are not
// printed as 0.0000).
std::string metric(double v)
{
    if (!finite(v)) return "n/a";
    if (v == 0.0 || std::fabs(v) >= 0.01) return fixed(v, 4);
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.2e", v);
    return buffer;
}

std::string withThousands(size_t v)
{
    std::string s = std::to_string(v);
    for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(size_t(i), ",");
    return s;
}

// Failure reasons become numbered notes under a table; cells say "failed [n]".
class Notes {
public:
    std::string cell(const Measured& m)
    {
        if (m.ok) return metric(m.cd) + " / " + metric(m.hd);
        return note(m.failure.empty() ? "not measured" : m.failure);
    }
    std::string note(const std::string& text)
    {
        auto [it, added] = index_.try_emplace(text, index_.size() + 1);
        if (added) order_.push_back(text);
        return "failed [" + std::to_string(it->second) + "]";
    }
    std::string flush()
    {
        std::string out;
        for (size_t i = 0; i < order_.size(); ++i) out += "- [" + std::to_string(i + 1) + "] " + order_[i] + "\n";
        index_.clear();
        order_.clear();
        return out.empty() ? out : "\n" + out;
    }

private:
    std::map<std::string, size_t> index_;
    std::vector<std::string> order_;
};

void writeText(const fs::path& path, const std::string& text)
{
    writeFileAtomic(path, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
}

// Mean over meshes of the cells that are all ok; NaN if any is missing.
std::pair<double, double> meanOf(const std::vector<const Measured*>& cells)
{
    double cd = 0.0, hd = 0.0;
    for (const Measured* m : cells) {
        if (!m || !m->ok) return {kNaN, kNaN};
        cd += m->cd;
        hd += m->hd;
    }
    if (cells.empty()) return {kNaN, kNaN};
    return {cd / double(cells.size()), hd / double(cells.size())};
}

std::string plotCaption(const ReportOptions& o) { return "made by: " + o.command; }

// The budget the cross-mesh table shows: 16 KB, or the listed budget nearest to it.
size_t tableBudget(const std::vector<size_t>& budgets)
{
    size_t best = budgets.front();
    for (size_t b : budgets)
        if (std::llabs((long long)b - 16384) < std::llabs((long long)best - 16384)) best = b;
    return best;
}

std::string budgetName(size_t bytes)
{
    return bytes % 1024 == 0 ? std::to_string(bytes / 1024) + " KB" : withThousands(bytes) + " B";
}

const BudgetRow* rowAt(const MeshReport& m, size_t budget)
{
    for (const BudgetRow& r : m.budgets)
        if (r.budget == budget) return &r;
    return nullptr;
}

// The largest chart's stored resolution, and the chart count where there are several.
std::string storedCell(const BudgetRow& r)
{
    return std::to_string(r.stored) + (r.charts > 1 ? " (" + std::to_string(r.charts) + " charts)" : "");
}

const Measured* bestPeerOf(const BudgetRow& r) { return r.bestPeer >= 0 ? &r.peers[size_t(r.bestPeer)].m : nullptr; }

// The rate-distortion section at byte budgets: the cross-mesh table at 16 KB with
// its win count, per mesh a table of every budget (CD and HD) and the CD plot.
void writeBudgetSection(std::ostringstream& md, Notes& notes, const ReportOptions& o,
                        const std::vector<MeshReport>& meshes, const std::string& command)
{
    if (o.budgets.empty()) return;
    md << "## Rate-distortion at byte budgets\n\n";
    md << "At each budget ngi is exactly the asset `ngi-bake MESH --resolution " << o.resolution
       << (o.resolution < 128 ? " --store-res " + std::to_string(o.resolution) : std::string())
       << " --target-bytes N` writes (its rate control picks the stored level and position step; it names "
          "the shipped network that restores that level, if any, with its fitted residual gain; networks from "
       << (o.networks.empty() ? std::string("ngi-bake's default search path") : "`" + o.networks.string() + "`")
       << "; the network's own bytes are not counted), drawn at LoD 0 restored bicubically (\"ngi\", "
          "`ngi-eval mesh --bicubic`) and by the named network (\"ngi + network\", `ngi-eval mesh --sr`; "
          "where no network restores the asset it is the bicubic restore, marked \"= ngi\"). The peer is "
          "meshoptimizer + Draco (compression level 10, draco_codec.h's default) at the largest triangle "
          "count within the same budget, the best CD of qp 10, 12 and 14 (docs/DESIGN.md \"Metrics\"). As "
          "ngi-bake does, a bake that split a component for its thin parts is fitted beside one chart per "
          "component and the one closer to the input kept; \"stored\" is the largest chart's stored "
          "resolution, with the chart count where there are several. "
          "Unit: CD x1e-4, HD x1e-2; bytes. Command: "
       << command << ".\n\n";

    const size_t shown = tableBudget(o.budgets);
    md << "### All meshes at " << budgetName(shown) << "\n\n";
    md << "| mesh | triangles | ngi bytes | stored | CD ngi | CD ngi + network | peer qp | peer bytes | CD peer | "
          "ratio ngi + network / peer | HD ngi + network | HD peer "
          "|\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    int both = 0, wins = 0;
    for (const MeshReport& m : meshes) {
        const BudgetRow* r = rowAt(m, shown);
        md << "| " << m.name << " | " << withThousands(m.inputTriangles) << " | ";
        if (!r) {
            md << "n/a | | | | | | | | | |\n";
            continue;
        }
        if (r->ngiFits)
            md << withThousands(r->ngiBytes) << " | " << storedCell(*r) << " | ";
        else
            md << notes.note(r->ngiFailure) << " | | ";
        const Measured* peer = bestPeerOf(*r);
        auto cd = [&](const Measured& v) {
            return v.ok ? metric(v.cd) : notes.note(v.failure.empty() ? "not measured" : v.failure);
        };
        md << (r->ngiFits ? cd(r->ngiBicubic) : "") << " | "
           << (r->ngiFits ? cd(r->ngiNetwork) + (r->networkRestores ? "" : " (= ngi)") : "") << " | ";
        if (peer) {
            const PeerAtQp& p = r->peers[size_t(r->bestPeer)];
            md << p.qp << " | " << withThousands(p.dracoBytes) << (r->wholeInputFits ? " (whole input)" : "") << " | "
               << metric(peer->cd) << " | ";
        } else {
            md << " | | " << notes.note("no peer within the budget") << " | ";
        }
        if (peer && r->ngiNetwork.ok && peer->cd > 0.0) {
            ++both;
            wins += r->ngiNetwork.cd < peer->cd ? 1 : 0;
            char ratio[32];
            std::snprintf(ratio, sizeof ratio, "%.3g", r->ngiNetwork.cd / peer->cd);
            md << ratio << (r->ngiNetwork.cd < peer->cd ? " (ngi wins)" : " (peer wins)");
        } else {
            md << "n/a";
        }
        // HD beside: the CD ratio decides the win; HD shows where the peer's worst error is lower.
        md << " | " << (r->ngiFits && r->ngiNetwork.ok ? metric(r->ngiNetwork.hd) : "n/a") << " | "
           << (peer ? metric(peer->hd) : "n/a") << " |\n";
    }
    md << notes.flush() << "\n";
    md << "**ngi wins on " << wins << " of " << both << " meshes at " << budgetName(shown)
       << "** (CD of ngi + network below the peer's best qp; of the meshes where both were measured"
       << (size_t(both) < meshes.size() ? ", " + std::to_string(meshes.size() - size_t(both)) + " not" : "")
       << ").\n\n";

    for (const MeshReport& m : meshes) {
        md << "### " << m.name << " at every budget\n\n";
        if (!m.budgetBakeFailure.empty()) md << "The bake failed: " << m.budgetBakeFailure << "\n\n";
        md << "| budget | ngi bytes | stored | step /65536 | network (gain) | ngi CD / HD | ngi + network CD / HD | "
              "peer qp 10 | peer qp 12 | peer qp 14 | best peer: qp, bytes, triangles | best peer CD / HD |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for (const BudgetRow& r : m.budgets) {
            md << "| " << withThousands(r.budget) << " | ";
            if (r.ngiFits)
                md << withThousands(r.ngiBytes) << " | " << storedCell(r) << " | " << r.step << " | "
                   << (r.networkId.empty()
                           ? std::string("none")
                           : r.networkId + (r.networkRestores ? " (" + fixed(r.gain, 3) + ")" : " (does not restore)"))
                   << " | " << notes.cell(r.ngiBicubic) << " | "
                   << (r.networkRestores ? notes.cell(r.ngiNetwork) : "= ngi") << " | ";
            else
                md << notes.note(r.ngiFailure) << " | | | | | | ";
            for (const PeerAtQp& p : r.peers)
                md << (p.m.ok ? metric(p.m.cd) : notes.note(p.m.failure.empty() ? "not measured" : p.m.failure))
                   << " | ";
            if (const Measured* peer = bestPeerOf(r)) {
                const PeerAtQp& p = r.peers[size_t(r.bestPeer)];
                md << p.qp << ", " << withThousands(p.dracoBytes) << ", " << withThousands(p.m.triangles)
                   << (r.wholeInputFits ? " (whole input fits)" : "") << " | " << notes.cell(*peer) << " |\n";
            } else {
                md << "none within the budget | |\n";
            }
        }
        md << notes.flush() << "\n";

        std::vector<PlotSeries> series(3);
        series[0].name = "ngi (bicubic)";
        series[0].colour = "#1f77b4";
        series[0].dashed = true;
        series[1].name = "ngi + network";
        series[1].colour = "#1f77b4";
        series[2].name = "meshopt+Draco, best of qp 10/12/14";
        series[2].colour = "#d62728";
        for (const BudgetRow& r : m.budgets) {
            if (r.ngiFits) {
                series[0].points.push_back({double(r.ngiBytes), r.ngiBicubic.ok ? r.ngiBicubic.cd : kNaN});
                series[1].points.push_back({double(r.ngiBytes), r.ngiNetwork.ok ? r.ngiNetwork.cd : kNaN});
            }
            if (const Measured* peer = bestPeerOf(r))
                series[2].points.push_back({double(r.peers[size_t(r.bestPeer)].dracoBytes), peer->cd});
        }
        SvgPlotOptions po;
        po.title = m.name + ": Chamfer distance against bytes (budgets)";
        po.xLabel = "bytes on disk (log)";
        po.yLabel = "CD x1e-4 (log)";
        po.caption = plotCaption(o);
        po.logX = po.logY = true;
        const std::string file = "plots/rd_budget_cd_" + m.name + ".svg";
        writeText(o.outDir / file, makeSvgLinePlot(series, po).svg);
        md << "![" << po.title << "](" << file << ")\n\n";
    }
}

// report.md, section by section, in reading order (each method appends its section to md;
// failures become numbered notes under each table).
struct ReportPage {
    std::ostringstream md;
    Notes notes;
    const ReportOptions& o;
    const std::vector<MeshReport>& meshes;
    const std::string command;      // the report's command line, quoted as code
    const std::string networkNote;  // what the SR cells say

    // The title, the metric, the resolution, the network and the meshes.
    void header(double seconds)
    {
        md << "# ngi evaluation report\n\n";
        md << "Produced by " << command << " in " << fixed(seconds / 60.0, 1) << " min.\n\n";
        md << "- Metric (docs/DESIGN.md \"Metrics\"): both meshes in the input mesh's frame (bounding-box centre, "
              "longest "
              "side 1); "
           << o.sampleCount
           << " area-uniform samples per surface, fixed seed; point-to-surface "
              "distances (CGAL AABB tree). **CD x1e-4** (mean squared distance, both ways), **HD x1e-2** (max). "
              "Cells read `CD / HD`.\n";
        md << "- Full geometry image: " << o.resolution << " x " << o.resolution << " cells (" << o.resolution + 1
           << "^2 samples). CR = " << o.resolution
           << "^2 / stored^2 (the paper's pixel ratio, "
              "full / stored cells squared: 1024^2 / 128^2 = 64 at the paper's resolution); \"restored x\" = "
              "full / stored, the upsampling factor the restore undoes.\n";
        if (!o.resolutionNote.empty()) md << "- Note: " << o.resolutionNote << "\n";
        md << "- Super-resolution: " << networkNote
           << "; every ngi number here is the **bilinear restore "
              "without SR** (`ngi-eval mesh ASSET --lod 0 --no-sr`).\n";
        md << "- Meshes:";
        for (const MeshReport& m : meshes)
            md << " " << m.name << " (" << withThousands(m.inputTriangles) << " triangles)";
        md << ".\n\n";
    }

    // Table 1 (each parameterization's full image) and the bakes.
    void table1()
    {
        // ---- Table 1.
        md << "## Table 1: parameterizations (full-resolution image against the input)\n\n";
        md << "The mesh of the FULL " << o.resolution
           << "^2 geometry image of each map (the asset storing mip "
              "level 0, drawn at LoD 0, shorter-diagonal split as the renderer draws it) against the input: the "
              "map's own sampling quality, no mip loss. Unit: CD x1e-4 / HD x1e-2. Command: "
           << command << ".\n\n";
        md << "| parameterization |";
        for (const MeshReport& m : meshes) md << " " << m.name << " |";
        md << " mean |\n|---|";
        for (size_t i = 0; i <= meshes.size(); ++i) md << "---|";
        md << "\n";
        for (size_t p = 0; p < o.parameterizations.size(); ++p) {
            md << "| " << parameterizationName(o.parameterizations[p]) << " |";
            std::vector<const Measured*> cells;
            for (const MeshReport& m : meshes) {
                const Measured* cell = p < m.bakes.size() ? &m.bakes[p].full : nullptr;
                cells.push_back(cell);
                md << " " << (cell ? notes.cell(*cell) : "n/a") << " |";
            }
            const auto [cd, hd] = meanOf(cells);
            md << " " << (finite(cd) ? metric(cd) + " / " + metric(hd) : "n/a") << " |\n";
        }
        md << notes.flush() << "\n";

        md << "Bakes (time, mean area distortion, mean angle distortion as the baker reports them):\n\n";
        md << "| mesh | parameterization | bake s | area distortion | angle distortion |\n|---|---|---|---|---|\n";
        for (const MeshReport& m : meshes)
            for (const BakeRow& b : m.bakes)
                md << "| " << m.name << " | " << b.method << " | "
                   << (b.reused ? (finite(b.seconds) ? fixed(b.seconds, 1) + " (reused)" : std::string("reused"))
                                : fixed(b.seconds, 1))
                   << " | " << (b.ok ? fixed(b.areaDistortionMean, 3) : notes.note("bake failed: " + b.failure))
                   << " | " << (b.ok ? fixed(b.angleDistortionMean, 3) : "") << " |\n";
        md << notes.flush() << "\n";
    }

    // Table 4 (the OT image at each stored resolution).
    void table4()
    {
        // ---- Table 4.
        md << "## Table 4: stored resolution (OT, restored without SR)\n\n";
        md << "The OT image stored at each resolution (the nested mip level the baker keeps), restored to "
           << o.resolution
           << "^2 by bilinear upsampling and drawn at LoD 0. Unit: CD x1e-4 / HD x1e-2. "
              "Command: "
           << command << ".\n\n";
        md << "| stored | CR | restored x |";
        for (const MeshReport& m : meshes) md << " " << m.name << " |";
        md << " mean | with SR |\n|---|---|---|";
        for (size_t i = 0; i <= meshes.size() + 1; ++i) md << "---|";
        md << "\n";
        for (size_t s = 0; s < o.storedResolutions.size(); ++s) {
            const uint32_t stored = o.storedResolutions[s];
            md << "| " << stored << " x " << stored << " | " << fixed(compressionRatio(o.resolution, stored), 0)
               << " | " << o.resolution / stored << " |";
            std::vector<const Measured*> cells;
            for (const MeshReport& m : meshes) {
                const Measured* cell = s < m.stored.size() ? &m.stored[s].ngi : nullptr;
                cells.push_back(cell);
                md << " " << (cell ? notes.cell(*cell) : "n/a") << " |";
            }
            const auto [cd, hd] = meanOf(cells);
            md << " " << (finite(cd) ? metric(cd) + " / " + metric(hd) : "n/a") << " | " << networkNote << " |\n";
        }
        md << notes.flush() << "\n";
    }

    // The peers at equal bytes per mesh, and who wins.
    void peersAtEqualBytes()
    {
        // ---- Peers.
        md << "## Peers at equal bytes\n\n";
        md << "For each stored resolution: the ngi asset's real bytes on disk (the whole .ngi file: header + "
              "POSI positions + NORM normals + META bake report and seam, each deflated), the network's bytes "
              "separately ("
           << networkNote
           << ": 0 bytes counted). The peer is the input simplified by "
              "meshoptimizer (QSlim-style) to the largest triangle count whose **Draco** encoding (14-bit "
              "positions, level 10, positions + connectivity only) fits the same file bytes, measured as "
              "decoded. Loop and modified-Butterfly subdivision of that decoded mesh (k iterations, the fewest "
              "reaching the input's triangle count, at most 3) are the paper's subdivision baselines at the "
              "same bytes. Unit: CD x1e-4 / HD x1e-2; bytes. Command: "
           << command << ".\n\n";
        for (const MeshReport& m : meshes) {
            md << "### " << m.name << " (" << withThousands(m.inputTriangles)
               << " triangles; whole input as Draco: " << withThousands(m.inputDracoBytes) << " bytes)\n\n";
            md << "| stored | CR | ngi file bytes (POSI / NORM / META) | network bytes | ngi no SR | "
                  "meshopt+Draco bytes, triangles | meshopt+Draco | Loop | Butterfly |\n"
                  "|---|---|---|---|---|---|---|---|---|\n";
            for (const StoredRow& r : m.stored) {
                md << "| " << r.stored << " | " << fixed(r.compressionRatio, 0) << " | ";
                if (r.bytes.file)
                    md << withThousands(r.bytes.file) << " (" << withThousands(r.bytes.positions) << " / "
                       << withThousands(r.bytes.normals) << " / " << withThousands(r.bytes.metadata) << ")";
                else
                    md << "n/a";
                md << " | 0 | " << notes.cell(r.ngi) << " | ";
                if (r.dracoBytes)
                    md << withThousands(r.dracoBytes) << ", " << withThousands(r.equalBytes.triangles)
                       << (r.wholeInputFits ? " (whole input fits)" : "") << (r.budgetMet ? "" : " (over budget)");
                else
                    md << "n/a";
                md << " | " << notes.cell(r.equalBytes) << " | " << notes.cell(r.loop)
                   << (r.loop.ok ? " (x" + std::to_string(r.subdivisionIterations) + ")" : "") << " | "
                   << notes.cell(r.butterfly) << " |\n";
            }
            md << notes.flush() << "\n";
        }

        // Who wins at equal bytes, counted over the meshes where both were measured.
        md << "Summary at equal bytes: meshes where ngi (no SR) has the lower CD / the lower HD than each peer, "
              "out of the meshes where both were measured.\n\n";
        md << "| stored | vs meshopt+Draco (CD, HD) | vs Loop (CD, HD) | vs Butterfly (CD, HD) |\n|---|---|---|---|\n";
        for (size_t s = 0; s < o.storedResolutions.size(); ++s) {
            md << "| " << o.storedResolutions[s] << " |";
            for (int peer = 0; peer < 3; ++peer) {
                int both = 0, cdWins = 0, hdWins = 0;
                for (const MeshReport& m : meshes) {
                    if (s >= m.stored.size()) continue;
                    const StoredRow& r = m.stored[s];
                    const Measured& other = peer == 0 ? r.equalBytes : peer == 1 ? r.loop : r.butterfly;
                    if (!r.ngi.ok || !other.ok) continue;
                    ++both;
                    cdWins += r.ngi.cd < other.cd ? 1 : 0;
                    hdWins += r.ngi.hd < other.hd ? 1 : 0;
                }
                md << " " << cdWins << ", " << hdWins << " of " << both << " |";
            }
            md << "\n";
        }
        md << "\n";
    }

    // The stored grid against meshoptimizer at its triangle count.
    void peersAtEqualTriangles()
    {
        md << "## Peers at equal triangle count\n\n";
        md << "The stored level's own grid as the renderer draws it (LoD = stored level: (stored+1)^2 vertices, "
              "2 stored^2 triangles, the stored samples themselves) against the input simplified by meshoptimizer "
              "to the same triangle count (the input itself when it has fewer triangles: CD there is the "
              "input's own, ~0). Unit: CD x1e-4 / HD x1e-2. Command: "
           << command << ".\n\n";
        md << "| mesh | stored | triangles | ngi grid | meshopt |\n|---|---|---|---|---|\n";
        for (const MeshReport& m : meshes)
            for (const StoredRow& r : m.stored)
                md << "| " << m.name << " | " << r.stored << " | "
                   << (r.ngiGrid.triangles ? withThousands(r.ngiGrid.triangles) : std::string("n/a")) << " | "
                   << notes.cell(r.ngiGrid) << " | " << notes.cell(r.simplifiedEqualTriangles)
                   << (r.inputHasFewerTriangles ? " (input: " + withThousands(m.inputTriangles) + " triangles)" : "")
                   << " |\n";
        md << notes.flush() << "\n";
    }

    // The rate-distortion and LoD plots (written to plots/) and the LoD tables.
    void plots()
    {
        // ---- Plots.
        md << "## Plots\n\n";
        md << "Rate-distortion per mesh: error against bytes, log-log, one curve per method (ngi = whole .ngi "
              "file; dashed: its POSI chunk alone; peers = Draco bytes of the stored coarse mesh). Points that "
              "failed or are 0 are left out. Made by "
           << command << ".\n\n";
        for (const MeshReport& m : meshes) {
            for (const bool chamfer : {true, false}) {
                std::vector<PlotSeries> series(5);
                series[0].name = "ngi (no SR)";
                series[1].name = "ngi POSI only";
                series[1].dashed = true;
                series[1].colour = "#1f77b4";
                series[0].colour = "#1f77b4";
                series[2].name = "meshopt+Draco";
                series[2].colour = "#d62728";
                series[3].name = "Loop";
                series[3].colour = "#2ca02c";
                series[4].name = "Butterfly";
                series[4].colour = "#ff7f0e";
                auto value = [&](const Measured& v) { return !v.ok ? kNaN : chamfer ? v.cd : v.hd; };
                for (const StoredRow& r : m.stored) {
                    series[0].points.push_back({double(r.bytes.file), value(r.ngi)});
                    series[1].points.push_back({double(r.bytes.positions), value(r.ngi)});
                    series[2].points.push_back({double(r.dracoBytes), value(r.equalBytes)});
                    series[3].points.push_back({double(r.dracoBytes), value(r.loop)});
                    series[4].points.push_back({double(r.dracoBytes), value(r.butterfly)});
                }
                SvgPlotOptions po;
                po.title = m.name + ": " + (chamfer ? "Chamfer distance" : "Hausdorff distance") + " against bytes";
                po.xLabel = "bytes on disk (log)";
                po.yLabel = chamfer ? "CD x1e-4 (log)" : "HD x1e-2 (log)";
                po.caption = plotCaption(o);
                po.logX = po.logY = true;
                const std::string file = "plots/rd_" + std::string(chamfer ? "cd_" : "hd_") + m.name + ".svg";
                writeText(o.outDir / file, makeSvgLinePlot(series, po).svg);
                md << "![" << po.title << "](" << file << ")\n";
            }
            md << "\n";
        }
        for (const MeshReport& m : meshes) {
            if (m.lods.empty()) continue;
            std::vector<PlotSeries> series(2);
            series[0].name = "CD x1e-4";
            series[1].name = "HD x1e-2";
            for (const LodRow& l : m.lods) {
                series[0].points.push_back({double(l.lod), l.m.ok ? l.m.cd : kNaN});
                series[1].points.push_back({double(l.lod), l.m.ok ? l.m.hd : kNaN});
            }
            SvgPlotOptions po;
            po.title = m.name + ": error against LoD (OT, stored " + std::to_string(m.lodStored) + ", no SR)";
            po.xLabel = "LoD (0 = full " + std::to_string(o.resolution) + "^2 grid; +1 halves the grid)";
            po.yLabel = "CD x1e-4 and HD x1e-2 (log)";
            po.caption = plotCaption(o);
            po.logY = true;
            const std::string file = "plots/lod_" + m.name + ".svg";
            writeText(o.outDir / file, makeSvgLinePlot(series, po).svg);
            md << "CD/HD against LoD for " << m.name << " (OT asset stored at " << m.lodStored
               << ", restored without SR, every integer LoD the renderer draws). Made by " << command << ".\n\n";
            md << "![" << po.title << "](" << file << ")\n\n";
            md << "| LoD | grid | triangles | CD x1e-4 / HD x1e-2 |\n|---|---|---|---|\n";
            for (const LodRow& l : m.lods)
                md << "| " << l.lod << " | " << l.gridSize << " | " << withThousands(l.m.triangles) << " | "
                   << notes.cell(l.m) << " |\n";
            md << notes.flush() << "\n";
        }
    }

    // The contact sheets and heat maps.
    void pictures()
    {
        // ---- Pictures.
        md << "## Pictures\n\n";
        md << "One contact sheet per mesh. Every tile is drawn by the same CPU z-buffer rasterizer (orthographic, "
              "flat shading, one light; back faces dark red), so tiles differ only by their triangles; the ngi LoD "
              "tiles are exactly the triangles the vertex shader draws (`ngi-eval mesh ASSET --lod F`) for the OT "
              "asset stored at "
           << (meshes.empty() ? 0u : meshes.front().lodStored)
           << ", restored without SR; peers (green) are at that asset's bytes. Tile side " << o.pictureSize
           << " pixels. Made by " << command << ".\n\n";
        for (const MeshReport& m : meshes) {
            md << "### " << m.name << "\n\n";
            if (m.pictureFile.empty()) {
                md << "No picture: " << m.pictureFailure << "\n\n";
                continue;
            }
            md << "![" << m.name << " contact sheet](" << m.pictureFile << ")\n\n";
            md << "Tiles, left to right, " << m.pictureColumns << " per row: ";
            for (size_t i = 0; i < m.pictureTiles.size(); ++i)
                md << (i ? "; " : "") << i + 1 << ". " << m.pictureTiles[i];
            md << ".\n\n";
            if (!m.heatMapFile.empty())
                md << "![" << m.name << " distance heat map](" << m.heatMapFile << ")\n\n"
                   << "Where ngi is far from the input: the input from two sides (yaw 35 and 215 degrees), each "
                      "triangle "
                      "coloured by its distance to ngi LoD 0 of the asset stored at "
                   << m.lodStored << " (the largest over its corners and centroid), log scale: red at the farthest, "
                   << fixed(m.heatMapFarthest, 3) << " x1e-2 of the size, blue at a hundredth of it.\n\n";
            else if (!m.heatMapFailure.empty())
                md << "No heat map: " << m.heatMapFailure << "\n\n";
        }
    }

    // What the output directory holds.
    void files()
    {
        md << "## Files\n\n";
        md << "- `assets/NAME.METHOD.full.ngi`: each map's full image (stored level 0; reused by `--reuse`); "
              "`assets/NAME.METHOD.failed.txt`: a bake's failure (also reused by `--reuse`).\n";
        md << "- `assets/NAME.ot.tN.ngi`: the asset of budget N, what `ngi-bake --target-bytes N` writes.\n";
        md << "- `assets/NAME.ot.sS.ngi`: the OT asset storing resolution S, exactly what `ngi-bake --store-res S` "
              "keeps from the same image (up to 16-bit rounding: it is cut from the stored full image); its size is "
              "the bytes column.\n";
    }
};

}  // namespace

fs::path writeReportFiles(const ReportOptions& o, const std::vector<MeshReport>& meshes, double seconds,
                          const std::string& networkNote)
{
    fs::create_directories(o.outDir / "plots");
    ReportPage page{{}, {}, o, meshes, "`" + o.command + "`", networkNote};
    page.header(seconds);
    page.table1();
    page.table4();
    page.peersAtEqualBytes();
    page.peersAtEqualTriangles();
    writeBudgetSection(page.md, page.notes, o, meshes, page.command);
    page.plots();
    page.pictures();
    page.files();
    const fs::path path = o.outDir / "report.md";
    writeText(path, page.md.str());
    return path;
}

}  // namespace ngi::report_detail
