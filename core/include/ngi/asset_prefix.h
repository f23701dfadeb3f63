// ngi core: streaming an asset. A format-5 file (ngi/asset.h) orders its positions coarse to
// fine, all charts' level 0 (the 2 x 2 corners), then all charts' level 1, ...: any prefix of
// the file that ends on a level boundary is a valid coarser asset. Show it, and refine as
// more bytes arrive (readAssetPrefix for bytes in hand, ProgressiveAssetReader for bytes that
// trickle in).
//
// What a prefix decodes to (an Asset like parseAsset's, every chart coarser):
//   - each chart at the finest level wholly in the prefix: storedLevel moved coarser by the
//     levels missing, positions BITWISE equal to the whole file's decode at that nested level
//     (its every 2^k-th sample: level L+1 = the even samples of level L), seam mates identical;
//   - normals: the prediction from those positions (pyramid_codec.h, the orientation POSI
//     records, mates copied), unless the chart is complete and its NORM residual is wholly in
//     the prefix; so a prefix's normals are NOT the full asset's normals subsampled;
//   - HEAD, CHRT, META and SEAM whole (they precede POSI); WGHT only if wholly in the prefix;
//   - coding: pyramid, progressive, the step of chart 0's finest decoded level.
// A prefix that ends between two level boundaries decodes to the boundary before it (the
// bytes past it wait for the rest of their level). Every byte a prefix decodes is checked:
// the chunk table's CRC, each description chunk's CRC, the level table's and each level's
// CRC32. parseAsset, the whole-file reader, still rejects every prefix.
#pragma once

#include "ngi/asset.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace ngi {

struct AssetPrefix {
    Asset asset;                     // the coarser asset
    uint32_t levelsDecoded = 0;      // levels (rounds) decoded, 1 .. levelCount
    uint32_t levelCount = 0;         // levels of the whole file (the most of any chart)
    bool complete = false;           // the whole file was read: asset is what parseAsset gives
    uint64_t boundaryBytes = 0;      // file bytes up to the boundary decoded (<= the prefix)
    uint64_t nextBoundaryBytes = 0;  // file bytes the next level needs (the file's size when
                                     // every level is in; a lower bound before the level table)
};

// Decodes the prefix `bytes` of an asset file. Format 5: the asset at the finest level
// boundary in `bytes` (see above). Formats 1-4 do not stream: only the whole file, which is
// read as parseAsset reads it. ngi::Error "NAME: problem" for a malformed prefix (as
// parseAsset would reject it), for one that ends before the coarsest level (saying how many
// bytes that needs), or a truncated file of format 1-4. Never reads out of bounds.
AssetPrefix readAssetPrefix(std::span<const uint8_t> bytes, const std::string& name);

// Accepts the bytes of an asset file as they arrive and decodes each level once it is
// complete, carrying the decoder's state on (the whole file costs one decode, not one per
// level). Typical use: on each network read append(chunk); if it returns true, build the
// engine's surface from current().asset and draw it instead of the previous one.
class ProgressiveAssetReader {
public:
    explicit ProgressiveAssetReader(std::string name);
    ~ProgressiveAssetReader();
    ProgressiveAssetReader(ProgressiveAssetReader&&) noexcept;
    ProgressiveAssetReader& operator=(ProgressiveAssetReader&&) noexcept;

    // Appends the next bytes of the file and decodes every level they complete. Returns true
    // if a finer level (or, at the end, the whole file with its optional chunks) became
    // available. Bytes past the file's declared end are ignored. ngi::Error "NAME: problem"
    // as soon as the bytes so far are malformed (what parseAsset would reject); after one,
    // every call throws it again.
    bool append(std::span<const uint8_t> bytes);

    uint64_t bytesReceived() const;
    uint32_t levelsDecoded() const;  // 0 until the coarsest level is in
    uint32_t levelCount() const;     // 0 until the level table (format 5) or the whole file is in
    bool complete() const;
    // File bytes needed for one more level: a lower bound while the chunk and level tables
    // are not in; the file's size once every level is.
    uint64_t bytesForNextLevel() const;
    // The asset at the finest level decoded (a copy: O(samples)). ngi::Error before the
    // coarsest level is in.
    AssetPrefix current() const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace ngi
