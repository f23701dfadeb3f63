#!/usr/bin/env python3
"""Re-encodes every image of a GLB as WebP (cwebp), scaled and at a quality, for the
appearance peer (tools/peer-appearance.sh): gltfpack's npm build has no texture codec, so its
output's PNG/JPEG images are replaced here and the textures marked EXT_texture_webp (required).

usage: peer-appearance-webp.py IN.glb OUT.glb SCALE QUALITY
  SCALE    texture side scale in (0, 1] (each side at least 1 texel, rounded)
  QUALITY  cwebp -q, 0..100
Prints the output's size in bytes. Standard library only; cwebp (Debian's webp) on PATH.
"""
import json
import os
import struct
import subprocess
import sys
import tempfile


def read_glb(path):
    data = open(path, "rb").read()
    magic, version, length = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67 or version != 2 or length != len(data):
        sys.exit(f"{path}: not a GLB 2.0 file")
    json_length, json_type = struct.unpack_from("<II", data, 12)
    document = json.loads(data[20:20 + json_length])
    at = 20 + json_length
    binary = b""
    if at < len(data):
        bin_length, bin_type = struct.unpack_from("<II", data, at)
        binary = data[at + 8:at + 8 + bin_length]
    return document, binary


def write_glb(path, document, binary):
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    out = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(binary))
    out += struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    with open(path, "wb") as f:
        f.write(out)
    return len(out)


def image_size(data):
    """Width and height of a PNG, JPEG or WebP from its header."""
    if data[:8] == b"\x89PNG\r\n\x1a\n":
        return struct.unpack(">II", data[16:24])
    if data[:2] == b"\xff\xd8":
        at = 2
        while at + 9 < len(data):
            if data[at] != 0xFF:
                at += 1
                continue
            marker = data[at + 1]
            if marker in (0xC0, 0xC1, 0xC2, 0xC3, 0xC5, 0xC6, 0xC7, 0xC9, 0xCA, 0xCB, 0xCD, 0xCE, 0xCF):
                height, width = struct.unpack(">HH", data[at + 5:at + 9])
                return width, height
            at += 2 + struct.unpack(">H", data[at + 2:at + 4])[0]
    sys.exit("an image is neither PNG nor JPEG")


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    source, target, scale, quality = sys.argv[1], sys.argv[2], float(sys.argv[3]), int(sys.argv[4])
    document, binary = read_glb(source)
    views = document.get("bufferViews", [])
    # The geometry's buffer views are kept, the images' dropped and appended re-encoded.
    image_views = {image["bufferView"] for image in document.get("images", []) if "bufferView" in image}
    # Regions of the BIN chunk: plain views, and the compressed data of EXT_meshopt_compression
    # views (whose own buffer is the uncompressed fallback).
    regions = []
    for index, view in enumerate(views):
        if index not in image_views and view.get("buffer", 0) == 0:
            regions.append(view)
        for name in ("EXT_meshopt_compression", "KHR_meshopt_compression"):
            extension = view.get("extensions", {}).get(name)
            if extension is not None and extension.get("buffer", 0) == 0:
                regions.append(extension)
    new_binary = b""
    copied = []
    for region in regions:
        new_binary += b"\0" * (-len(new_binary) % 4)
        start = region.get("byteOffset", 0)
        copied.append(len(new_binary))
        new_binary += binary[start:start + region["byteLength"]]
    for region, offset in zip(regions, copied):
        region["byteOffset"] = offset
    with tempfile.TemporaryDirectory() as scratch:
        for image in document.get("images", []):
            view = views[image["bufferView"]]
            start = view.get("byteOffset", 0)
            data = binary[start:start + view["byteLength"]]
            width, height = image_size(data)
            source_path, webp_path = os.path.join(scratch, "in"), os.path.join(scratch, "out.webp")
            open(source_path, "wb").write(data)
            w, h = max(1, round(width * scale)), max(1, round(height * scale))
            subprocess.run(["cwebp", "-quiet", "-q", str(quality), "-m", "6", "-resize", str(w), str(h),
                            source_path, "-o", webp_path], check=True)
            webp = open(webp_path, "rb").read()
            new_binary += b"\0" * (-len(new_binary) % 4)
            view["byteOffset"] = len(new_binary)
            view["byteLength"] = len(webp)
            view.pop("byteStride", None)
            new_binary += webp
            image["mimeType"] = "image/webp"
    if document.get("images"):
        for texture in document.get("textures", []):
            if "source" in texture:
                texture.setdefault("extensions", {})["EXT_texture_webp"] = {"source": texture.pop("source")}
        for key in ("extensionsUsed", "extensionsRequired"):
            document[key] = sorted(set(document.get(key, [])) | {"EXT_texture_webp"})
    # One buffer: the BIN chunk (gltfpack's meshopt fallback buffer, if any, keeps its index).
    document["buffers"][0]["byteLength"] = len(new_binary)
    print(write_glb(target, document, new_binary))


if __name__ == "__main__":
    main()
