// ngi-bake --batch: bakes a data set (DESIGN.md: batch, resumable, sharded), part of the ngi-bake tool.
//
//   ngi-bake --batch DIR_OR_LIST --out DIR [--jobs N] [--shard I/N] [--timeout SECONDS]
//            [--resolution R] [--store-res S] [--param METHOD] [--remesh-vertices N]
//            [--feature-angle DEG] [--free-seams] [--detail-density S] [--quiet]
//
// Inputs: every file of a directory with a mesh extension (.obj .off .ply .stl .gltf .glb,
// case-insensitive), sorted by name; or a text file of paths, one per line ('#' starts a
// comment line; relative paths are relative to the working directory, as in tar -T).
// Each input is baked by a child process (fork + exec of /proc/self/exe running the one-mesh
// ngi-bake), so a crash or a --timeout kills one bake, not the batch, and the bake library
// needs no thread safety. Outputs: DIR/NAME.ngi (NAME the file's stem; when two inputs
// share a stem, as pig.off and pig.stl, both use the whole file name: pig.off.ngi and
// pig.stl.ngi; two inputs with the same file name are refused up front), and one JSON line
// per input appended to DIR/summary.jsonl (DIR/summary.shard-I-of-N.jsonl with --shard, so
// shards on several machines never share a file; merge by concatenating them).
//
// Resume: an input is skipped when an earlier summary line (any DIR/summary*.jsonl) records
// it ok with the same input hash (FNV-1a 64 of its bytes, the asset's sourceHash), the same
// options fingerprint and the hash of the asset file now in DIR, and that asset's sourceHash
// is the input's hash. A skipped input gets a "skipped" line and its asset is not touched.
//
// Exit status: 0 if every input baked or was skipped, 1 if any failed, 2 on a usage error.
#pragma once

namespace ngi {

// True if the command line asks for a batch (holds --batch): main() then calls runBatch.
bool isBatchCommand(int argc, char** argv);

// Runs `ngi-bake --batch ...`: parses the command line, bakes, prints progress (stderr) and
// the final table (stdout). Returns the exit status (0, 1 or 2 as above). Never throws.
int runBatch(int argc, char** argv);

}  // namespace ngi
