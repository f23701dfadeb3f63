#!/usr/bin/env python3
"""The table of tools/peer-appearance.sh from its output folder: for each input and budget, ngi
(OUT/NAME.BUDGET.ngi.json, .ngi) and gltfpack's texture setting of the best Y PSNR, and, where
another one is closer in geometry, the setting of the smallest CD (OUT/NAME.BUDGET.peer.tsv).

usage: peer-appearance-table.py OUT NAME:BUDGET...
"""
import json
import os
import sys


def psnr(value):
    return "inf" if value == "inf" else ("-" if value is None else "%.2f" % value)


def number(text):
    return float("inf") if text == "inf" else (-1.0 if text == "-" else float(text))


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    print("| input | budget | | bytes | triangles | textures | CD x1e-4 | HD x1e-2 | PSNR Y / Cb / Cr dB |")
    print("|---|---|---|---|---|---|---|---|---|")
    for item in sys.argv[2:]:
        name, budget = item.rsplit(":", 1)
        base = os.path.join(out, f"{name}.{budget}")
        if os.path.exists(base + ".ngi.json"):
            j = json.load(open(base + ".ngi.json"))
            c = j.get("colour") or {}
            print(f"| {name} | {budget} | ngi | {os.path.getsize(base + '.ngi')} | {j['candidate']['triangles']} (LoD 0) "
                  f"| chart images | {j['chamfer_x1e-4']:.4f} | {j['hausdorff_x1e-2']:.3f} "
                  f"| {psnr(c.get('psnr_y'))} / {psnr(c.get('psnr_cb'))} / {psnr(c.get('psnr_cr'))} |")
        else:
            print(f"| {name} | {budget} | ngi | bake failed | | | | | |")
        rows = []
        if os.path.exists(base + ".peer.tsv"):
            rows = [line.split("\t") for line in open(base + ".peer.tsv").read().splitlines() if line]
        if not rows:
            print(f"| {name} | {budget} | gltfpack | nothing fits | | | | | |")
            continue
        best_colour = max(rows, key=lambda r: (number(r[7]), -float(r[5])))  # ties: the smaller CD
        best_geometry = min(rows, key=lambda r: (float(r[5]), -number(r[7])))
        for label, r in (("gltfpack, best Y", best_colour), ("gltfpack, best CD", best_geometry)):
            if label.endswith("CD") and r is best_colour:
                continue
            ratio, scale, quality, size, triangles, cd, hd, y, cb, cr = r
            textures = "the input's" if quality == "orig" else f"x{scale} WebP q{quality}"
            print(f"| {name} | {budget} | {label} | {size} | {triangles} (R {float(ratio):.3g}) | {textures} "
                  f"| {float(cd):.4f} | {float(hd):.3f} | {y} / {cb} / {cr} |")


if __name__ == "__main__":
    main()
