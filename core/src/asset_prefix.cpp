// Streaming an asset: the prefix readers of ngi/asset_prefix.h over format 5's layout
// (ngi/asset.h; asset_progressive.cpp decodes its POSI chunk).
#include "ngi/asset_prefix.h"

#include "asset_format.h"
#include "crc32.h"
#include "ngi/error.h"

#include <optional>
#include <vector>

namespace ngi {

using namespace detail;

struct ProgressiveAssetReader::State {
    std::string name;
    std::vector<uint8_t> bytes;
    std::optional<AssetLayout> layout;  // chunk spans point into `bytes` (refreshed)
    std::optional<Asset> description;   // format 5, once the bytes reach POSI
    std::optional<ProgressivePositions> positions;
    std::optional<Asset> whole;  // formats 1-4, once the whole file is in
    std::string error;           // set by the first failure
    bool complete = false;

    const AssetChunk& posi() const { return *layout->find(kPosi, 0, true, name); }

    // Marks the chunks the bytes now hold as present (checking each one's CRC once) and
    // points every present chunk's span into the current buffer.
    void refreshChunks()
    {
        for (AssetChunk& e : layout->chunks) {
            if (e.end() > bytes.size()) continue;
            e.bytes = std::span<const uint8_t>(bytes).subspan(size_t(e.offset), size_t(e.size));
            if (!e.present && crc32Of(e.bytes) != e.crc)
                throw Error(name + ": chunk " + fourccName(e.code) +
                            (e.code == kNorm || e.code == kSeam ? " of chart " + std::to_string(e.chart) : "") +
                            " fails its CRC32 check");
            e.present = true;
        }
    }

    void update()
    {
        if (!layout) {
            layout = readAssetLayout(bytes, name, true);
            if (!layout) return;
        }
        refreshChunks();
        if (layout->coding < 5) {
            if (!whole && bytes.size() >= layout->fileBytes) {
                whole = parseAsset(bytes, name);
                complete = true;
            }
            return;
        }
        const AssetChunk& p = posi();
        if (bytes.size() < p.offset) return;  // the description is not in yet
        if (!description) {
            description = readAssetDescription(*layout, name);
            positions.emplace(*description, name + ": chunk POSI", p.size);
        }
        const size_t available = size_t(std::min<uint64_t>(bytes.size() - p.offset, p.size));
        positions->advance(std::span<const uint8_t>(bytes).subspan(size_t(p.offset), available));
        complete = positions->tableRead() && positions->roundsDecoded() == positions->roundCount() &&
            bytes.size() >= layout->fileBytes;
    }

    uint32_t levelsDecoded() const
    {
        if (whole) return levelCountOf(*whole);
        return positions ? positions->roundsDecoded() : 0;
    }
    static uint32_t levelCountOf(const Asset& a)
    {
        uint32_t levels = 0;
        for (const AssetChart& c : a.charts) levels = std::max(levels, pyramidLevelCount(c.storedSize()));
        return levels;
    }
};

ProgressiveAssetReader::ProgressiveAssetReader(std::string name) : state_(std::make_unique<State>())
{
    state_->name = std::move(name);
}

ProgressiveAssetReader::~ProgressiveAssetReader() = default;
ProgressiveAssetReader::ProgressiveAssetReader(ProgressiveAssetReader&&) noexcept = default;
ProgressiveAssetReader& ProgressiveAssetReader::operator=(ProgressiveAssetReader&&) noexcept = default;

bool ProgressiveAssetReader::append(std::span<const uint8_t> bytes)
{
    State& s = *state_;
    if (!s.error.empty()) throw Error(s.error);
    if (s.layout && s.bytes.size() >= s.layout->fileBytes) return false;  // past the end: ignored
    const uint32_t before = s.levelsDecoded();
    const bool wasComplete = s.complete;
    size_t take = bytes.size();
    if (s.layout) take = size_t(std::min<uint64_t>(take, s.layout->fileBytes - s.bytes.size()));
    s.bytes.insert(s.bytes.end(), bytes.begin(), bytes.begin() + ptrdiff_t(take));
    try {
        s.update();
        // The layout may have been read from these very bytes: drop what lies past the file.
        if (s.layout && s.bytes.size() > s.layout->fileBytes) {
            s.bytes.resize(size_t(s.layout->fileBytes));
            s.update();
        }
    } catch (const Error& e) {
        s.error = e.what();
        throw;
    }
    return s.levelsDecoded() > before || (s.complete && !wasComplete);
}

uint64_t ProgressiveAssetReader::bytesReceived() const { return state_->bytes.size(); }
uint32_t ProgressiveAssetReader::levelsDecoded() const { return state_->levelsDecoded(); }
bool ProgressiveAssetReader::complete() const { return state_->complete; }

uint32_t ProgressiveAssetReader::levelCount() const
{
    const State& s = *state_;
    if (s.whole) return State::levelCountOf(*s.whole);
    return s.positions ? s.positions->roundCount() : 0;
}

uint64_t ProgressiveAssetReader::bytesForNextLevel() const
{
    const State& s = *state_;
    if (!s.layout) return std::max<uint64_t>(s.bytes.size() + 1, kAssetHeaderBytes + kChunkEntryBytes);
    if (s.layout->coding < 5) return s.layout->fileBytes;
    const AssetChunk& p = s.posi();
    if (!s.positions) return p.offset + 8;  // at least the description and a level table's start
    if (s.positions->tableRead() && s.positions->roundsDecoded() == s.positions->roundCount())
        return s.layout->fileBytes;
    return p.offset + s.positions->bytesForNextRound();
}

AssetPrefix ProgressiveAssetReader::current() const
{
    const State& s = *state_;
    if (!s.error.empty()) throw Error(s.error);
    AssetPrefix out;
    out.levelsDecoded = levelsDecoded();
    out.levelCount = levelCount();
    out.complete = s.complete;
    out.nextBoundaryBytes = bytesForNextLevel();
    if (s.whole) {
        out.asset = *s.whole;
        out.boundaryBytes = s.layout->fileBytes;
        return out;
    }
    if (out.levelsDecoded == 0) {
        const std::string need = std::to_string(out.nextBoundaryBytes) + " bytes";
        if (s.layout && s.layout->coding < 5)
            throw Error(s.name + ": the file is truncated (" + std::to_string(s.bytes.size()) + " of " +
                        std::to_string(s.layout->fileBytes) + " bytes), and format " +
                        std::to_string(s.layout->version) + " assets" +
                        (s.layout->version == s.layout->coding
                             ? std::string()
                             : " laid out as format " + std::to_string(s.layout->coding)) +
                        " do not stream (format 5's layout does)");
        throw Error(s.name + ": the prefix (" + std::to_string(s.bytes.size()) +
                    " bytes) ends before the coarsest level" + " (at least " + need + " needed)");
    }
    Asset a = *s.description;
    finishProgressiveAsset(*s.layout, *s.positions, a, s.name);
    readChartColors(*s.layout, a, s.name);
    if (const AssetChunk* w = s.layout->find(kWght, 0, false, s.name); w && w->present) {
        if (w->encoding != kRaw) throw Error(s.name + ": chunk WGHT must be stored raw");
        a.weights.assign(w->bytes.begin(), w->bytes.end());
    }
    out.asset = std::move(a);
    const AssetChunk& p = s.posi();
    out.boundaryBytes = s.complete ? s.layout->fileBytes : p.offset + s.positions->decodedBytes();
    return out;
}

AssetPrefix readAssetPrefix(std::span<const uint8_t> bytes, const std::string& name)
{
    ProgressiveAssetReader reader(name);
    reader.append(bytes);
    return reader.current();
}

}  // namespace ngi
