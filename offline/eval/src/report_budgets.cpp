// ngi offline eval, the report's rate-distortion rows (report_job.h measureBudgetRows): the
// asset ngi-bake --target-bytes writes at each byte budget against meshoptimizer + Draco's best
// precision at the same budget.
#include "report_job.h"

#include "ngi/asset.h"
#include "ngi/bake/bake.h"
#include "ngi/bake/network_choice.h"
#include "ngi/bake/rate_control.h"
#include "ngi/eval/asset_mesh.h"
#include "ngi/eval/equal_bytes.h"
#include "ngi/output_files.h"

#include <algorithm>
#include <optional>

namespace ngi::report_detail {

namespace fs = std::filesystem;

namespace {

// Draco position precisions of the peer at a budget (docs/DESIGN.md "Metrics").
constexpr int kPeerQps[] = {10, 12, 14};

// The peer at `budget`: each precision's largest simplification within it, measured; the
// best is the smallest CD among those within the budget.
void measurePeers(MeshContext& mesh, BudgetRow& row)
{
    const TriangleMesh& input = mesh.input;
    const std::string step = std::to_string(row.budget) + " B";
    for (int qp : kPeerQps) {
        PeerAtQp peer;
        peer.qp = qp;
        try {
            EqualBytesOptions eo;
            eo.draco.positionQuantizationBits = qp;
            const EqualBytesResult r = simplifyToByteBudget(input, row.budget, eo);
            peer.dracoBytes = r.dracoBytes;
            peer.budgetMet = r.budgetMet;
            peer.m = mesh.measure(r.decoded, step + " peer qp" + std::to_string(qp));
            if (!r.budgetMet && peer.m.ok) {
                peer.m.ok = false;
                peer.m.failure =
                    "over budget: the smallest simplification takes " + std::to_string(r.dracoBytes) + " bytes";
            }
            const int index = int(row.peers.size());
            if (peer.m.ok && (row.bestPeer < 0 || peer.m.cd < row.peers[size_t(row.bestPeer)].m.cd)) {
                row.bestPeer = index;
                row.wholeInputFits = r.simplified.triangles.size() == input.triangles.size();
            }
        } catch (const std::exception& e) {
            peer.m.failure = "failed: " + oneLine(e.what());
            mesh.progress.advance(1.0, mesh.report.name + ": " + step + " peer qp" + std::to_string(qp));
        }
        row.peers.push_back(std::move(peer));
    }
}

}  // namespace

// Per budget exactly ngi-bake --target-bytes' sequence (ngi_bake_main.cpp): reserve the network
// fields, fit the asset to the budget, name the network and fit its gains, serialize.
void measureBudgetRows(MeshContext& mesh, std::span<const ShippedNetwork> shipped)
{
    const ReportOptions& options = mesh.options;
    const TriangleMesh& input = mesh.input;
    ProgressSink& progress = mesh.progress;
    MeshReport& report = mesh.report;
    if (options.budgets.empty()) return;
    std::optional<BakeResult> baked, whole;
    BakeOptions bake;  // ngi-bake's defaults but the resolution
    bake.resolution = options.resolution;
    // ngi-bake --resolution R below 128 needs --store-res <= R; the rate control replaces
    // the stored level whatever it is.
    bake.storeResolution = std::min(bake.storeResolution, options.resolution);
    bake.sourceName = report.path;
    bake.sourceHash = mesh.sourceHash;
    try {
        baked = bakeMesh(input, bake);
        baked->asset.sourceName = fs::path(report.path).filename().string();
        reserveNetworkFields(baked->asset, shipped);
    } catch (const std::exception& e) {
        report.budgetBakeFailure = oneLine(e.what());
    }
    // As ngi-bake --target-bytes: a split for thin parts competes at each budget with one
    // chart per component (kept where the rate control finds it closer to the input); where
    // that bake is refused (cheese), the split stays.
    if (baked && anyComponentSplitForThinParts(baked->report)) {
        BakeOptions wholeOptions = bake;
        wholeOptions.splitThinParts = 0;
        try {
            whole = bakeMesh(input, wholeOptions);
            whole->asset.sourceName = baked->asset.sourceName;
            reserveNetworkFields(whole->asset, shipped);
        } catch (const std::exception&) {}
    }
    progress.advance(kBakeUnits, report.name + ": bake for the budgets");
    for (size_t budget : options.budgets) {
        BudgetRow row;
        row.budget = budget;
        const std::string step = std::to_string(budget) + " B";
        if (!baked) {
            row.ngiFailure = "failed: bake " + report.budgetBakeFailure;
            row.ngiBicubic.failure = row.ngiNetwork.failure = row.ngiFailure;
            progress.advance(2.0, report.name + ": " + step + " (no bake)");
        } else {
            try {
                Asset asset = baked->asset;
                std::optional<Asset> oneChart;
                if (whole) oneChart = whole->asset;
                const BudgetChoice fit =
                    fitCloserOfTwoBakes(asset, baked->charts, oneChart ? &*oneChart : nullptr,
                                        whole ? &whole->charts : nullptr, budget, 0, shipped, input);
                const RateControlReport& rate = fit.kept();
                const std::vector<ChartBake>* charts = &baked->charts;
                if (!fit.keptFirst) {
                    asset = std::move(*oneChart);
                    charts = &whole->charts;
                }
                const NetworkChoice choice = nameNetworkAndFitGains(asset, *charts, shipped);
                const std::vector<uint8_t> file = serializeAsset(asset);
                const fs::path path = mesh.assetPath("ot", "t" + std::to_string(budget) + ".ngi");
                writeFileAtomic(path, file);
                row.ngiFits = true;
                row.ngiBytes = file.size();
                row.assetFile = fs::relative(path, options.outDir).string();
                row.stored = asset.fullResolution() >> rate.chosen.storedLevel;
                row.charts = asset.charts.size();
                row.step = rate.chosen.step;
                const Asset decoded = parseAsset(file, path.string());  // as a reader decodes it
                row.ngiBicubic = mesh.measure(assetMesh(decoded, {.lod = 0.0f, .restore = AssetRestore::Bicubic}).mesh,
                                              step + " ngi bicubic");
                if (choice.named) {
                    row.networkId = choice.named->network.name;
                    row.networkRestores = networkRestoresChart(choice.named->network, decoded.charts.front());
                    row.gain = decoded.charts.front().residualGain;
                }
                if (choice.named && row.networkRestores) {
                    const AssetMeshOptions sr{
                        .lod = 0.0f, .restore = AssetRestore::Network, .network = &choice.named->network};
                    row.ngiNetwork = mesh.measure(assetMesh(decoded, sr).mesh, step + " ngi + network");
                } else {
                    row.ngiNetwork = row.ngiBicubic;
                    progress.advance(1.0, report.name + ": " + step + " no network");
                }
            } catch (const std::exception& e) {
                row.ngiFailure = (row.ngiFits ? "failed: " : "no asset: ") + oneLine(e.what());
                for (Measured* m : {&row.ngiBicubic, &row.ngiNetwork})
                    if (!m->ok && m->failure.empty()) m->failure = row.ngiFailure;
                progress.advance(0.0, report.name + ": " + step + " ngi failed");
            }
        }
        measurePeers(mesh, row);
        report.budgets.push_back(std::move(row));
    }
}

}  // namespace ngi::report_detail
