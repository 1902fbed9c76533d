#!/usr/bin/env bash
# Regenerates the libFuzzer seed corpora in fuzz/corpus/<target>/ from ../shared/assets, the scene
# files in scenes/data/ and the style presets in stylize/presets/ (fuzz/README.md "Seeds").
# Usage: scripts/make_fuzz_corpus.sh [--shared DIR] [--out DIR]
#   --shared DIR  the shared folder (default: $AQ_SHARED, else ../shared beside the checkout)
#   --out DIR     where to write (default: fuzz/corpus; the folders are emptied of seed-* files first)
# Deterministic: the same assets give the same bytes. Needs python3 only (standard library).
# Only small files are kept (every seed < 64 KiB, the whole folder well under 3 MB): large buffers
# are replaced by the fuzzer's own buffer.bin, large images by its tex.png (fuzz/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."
shared="${AQ_SHARED:-../shared}"
out=fuzz/corpus
while [ $# -gt 0 ]; do
  case "$1" in
    --shared) shared="$2"; shift ;;
    --out) out="$2"; shift ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) echo "make_fuzz_corpus.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
[ -d "$shared/assets" ] || { echo "make_fuzz_corpus.sh: $shared/assets not found (use --shared)" >&2; exit 1; }

python3 - "$shared/assets" "$out" <<'PY'
import base64, json, os, struct, sys, zlib

assets, out = sys.argv[1], sys.argv[2]
MAX_SEED = 64 * 1024

def target_dir(t):
    d = os.path.join(out, t)
    os.makedirs(d, exist_ok=True)
    for f in os.listdir(d):
        if f.startswith("seed-"):
            os.remove(os.path.join(d, f))
    return d

def put(d, name, data):
    if isinstance(data, str):
        data = data.encode()
    assert len(data) <= MAX_SEED, (name, len(data))
    with open(os.path.join(d, "seed-" + name), "wb") as f:
        f.write(data)

def read(rel):
    with open(os.path.join(assets, rel), "rb") as f:
        return f.read()

def compact(obj):
    return json.dumps(obj, separators=(",", ":"), sort_keys=True)

def data_uri(b, mime):
    return "data:%s;base64,%s" % (mime, base64.b64encode(b).decode())

# --- glTF ------------------------------------------------------------------------------------------
# Buffers up to MAX_BUF bytes and images up to MAX_IMG bytes are embedded as data URIs; larger ones
# are pointed at the fuzzer's buffer.bin / tex.png (fuzz/fuzz_gltf.cpp), keeping the JSON.
MAX_BUF, MAX_IMG = 32 * 1024, 4 * 1024

def embed(rel):
    base = os.path.dirname(rel)
    g = json.loads(read(rel))
    for b in g.get("buffers", []):
        uri = b.get("uri", "")
        if uri and not uri.startswith("data:"):
            p = os.path.join(assets, base, uri)
            if os.path.exists(p) and os.path.getsize(p) <= MAX_BUF:
                b["uri"] = data_uri(read(os.path.join(base, uri)), "application/octet-stream")
            else:
                b["uri"] = "buffer.bin"
    for im in g.get("images", []):
        uri = im.get("uri", "")
        if uri and not uri.startswith("data:"):
            p = os.path.join(assets, base, uri)
            if os.path.exists(p) and os.path.getsize(p) <= MAX_IMG:
                im["uri"] = data_uri(read(os.path.join(base, uri)), "image/png")
            else:
                im["uri"] = "tex.png"
    return g

def glb(g, bin_bytes):
    js = compact(g).encode()
    js += b" " * (-len(js) % 4)
    chunks = struct.pack("<II", len(js), 0x4E4F534A) + js
    if bin_bytes is not None:
        bin_bytes += b"\0" * (-len(bin_bytes) % 4)
        chunks += struct.pack("<II", len(bin_bytes), 0x004E4942) + bin_bytes
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks

def to_glb(rel, image_to_bufferview=True):
    """The model as GLB: buffer 0 becomes the BIN chunk; small images move into bufferViews."""
    base = os.path.dirname(rel)
    g = json.loads(read(rel))
    assert len(g["buffers"]) == 1
    b = bytearray(read(os.path.join(base, g["buffers"][0]["uri"])))
    del g["buffers"][0]["uri"]
    for im in g.get("images", []):
        p = os.path.join(assets, base, im.get("uri", ""))
        if image_to_bufferview and os.path.isfile(p) and os.path.getsize(p) <= MAX_IMG:
            b += b"\0" * (-len(b) % 4)
            g.setdefault("bufferViews", []).append({"buffer": 0, "byteOffset": len(b), "byteLength": os.path.getsize(p)})
            b += read(os.path.join(base, im["uri"]))
            del im["uri"]
            im["bufferView"] = len(g["bufferViews"]) - 1
            im["mimeType"] = "image/png"
        else:
            im["uri"] = "tex.png"
    g["buffers"][0]["byteLength"] = len(b)
    return glb(g, bytes(b))

d = target_dir("gltf")
for name, rel in [
    ("triangle-embedded.gltf", "gltf/Triangle/glTF-Embedded/Triangle.gltf"),
    ("box-embedded.gltf", "gltf/Box/glTF-Embedded/Box.gltf"),
    ("box-vertex-colors.gltf", "gltf/BoxVertexColors_CC0/glTF-Embedded/BoxVertexColors.gltf"),
    ("box-textured.gltf", "gltf/BoxTextured/BoxTextured.gltf"),
    ("cube.gltf", "gltf/Cube/glTF/Cube.gltf"),
    ("avocado.gltf", "gltf/Avocado/glTF/Avocado.gltf"),
    ("orientation-test.gltf", "gltf/OrientationTest/glTF/OrientationTest.gltf"),
    ("suzanne-json.gltf", "gltf/Suzanne/glTF/Suzanne.gltf"),
    ("waterbottle-json.gltf", "gltf/WaterBottle/glTF/WaterBottle.gltf"),
    ("fox-json.gltf", "gltf/Fox/glTF/Fox.gltf"),
]:
    put(d, name, compact(embed(rel)))
# The Triangle with its external buffer renamed to the fuzzer's buffer.bin (external-file path).
g = json.loads(read("gltf/Triangle/glTF/Triangle.gltf"))
g["buffers"][0]["uri"] = "buffer.bin"
g["buffers"][0]["byteLength"] = 256
put(d, "triangle-external.gltf", compact(g))
for f in sorted(os.listdir(os.path.join(assets, "conformance/Mesh_PrimitiveMode"))):
    if f.endswith(".gltf"):
        put(d, "conformance-" + f, compact(embed("conformance/Mesh_PrimitiveMode/" + f)))
for f in sorted(os.listdir(os.path.join(assets, "malformed"))):
    if f.endswith(".gltf"):
        put(d, "malformed-" + f, compact(embed("malformed/" + f)))
put(d, "box-textured.glb", to_glb("gltf/BoxTextured/BoxTextured.gltf"))
put(d, "cube.glb", to_glb("gltf/Cube/glTF/Cube.gltf"))
put(d, "triangle.glb", to_glb("gltf/Triangle/glTF/Triangle.gltf"))
put(d, "orientation-test.glb", read("gltf/OrientationTest/glTF-Binary/OrientationTest.glb"))

# --- scene files -----------------------------------------------------------------------------------
# Paths are renamed to the files the fuzzer writes beside scene.json (fuzz/fuzz_scene_file.cpp):
# model.gltf (materials "paint" and "second"), tex.png, paper.png.
def rename_paths(s):
    if "gltf" in s:
        s["gltf"] = "model.gltf"
    if "paper" in s:
        s["paper"] = "paper.png"
    for r in s.get("control", []):
        if "file" in r:
            r["file"] = "tex.png"
    m = s.get("materials")
    if isinstance(m, dict):
        s["materials"] = {("paint" if k not in ("*",) else k): v for k, v in m.items()}
    return s

d = target_dir("scene_file")
for f in sorted(os.listdir("scenes/data")):
    if f.endswith(".json"):
        with open(os.path.join("scenes/data", f)) as fh:
            put(d, f, json.dumps(rename_paths(json.load(fh)), indent=1))
extra = {
    "texture-rule.json": {"gltf": "model.gltf", "width": 64, "height": 48,
        "control": [{"target": "pigment", "source": "texture", "file": "tex.png", "scale": 2, "bias": -1},
                    {"target": "edge.width", "source": "COLOR_0.g", "materials": ["paint"]},
                    {"target": "substrate.distortion", "source": "TEXCOORD_0.x", "scale": 0.5},
                    {"target": "abstraction.b", "source": "noise", "noise": {"frequency": 2, "amplitude": 0.5, "seed": 7, "octaves": 2}}],
        "camera": {"eye": [0, 0, 5], "target": [0.5, 0.5, 0], "up": [0, 1, 0], "yfov_deg": 40, "near": 0.1, "far": 50}},
    "materials.json": {"gltf": "model.gltf", "scale": 2.5,
        "materials": {"*": {"dilute": 0.4}, "paint": {"cangiante": 0.3, "specular": 0.2}, "1": {"shade_wrap": 0.5}},
        "style": {"preset": "wc18", "set": {"pigment_density.strength": 0.5}, "variant": {"edge_detect": "rgbd"}},
        "substrate_color": [1, 0.98, 0.95], "fps": 30, "lights": [{"direction": [0, 1, 0], "intensity": 0.8}],
        "ambient": [0.1, 0.1, 0.1]},
    "wc17.json": {"gltf": "model.gltf", "control_layout": "wc17",
        "control": [{"target": "A", "source": "constant", "value": 0.7}, {"target": "granulation", "source": "POSITION.x"}],
        "camera": {"orthographic": True, "eye": [0, 0, 5], "target": [0, 0, 0], "ymag": 2}},
    "procedural.json": {"procedural": "swatches", "camera": {"auto": True, "view_dir": [0, -1, -1], "yfov": 0.5}},
}
for name, s in extra.items():
    put(d, name, json.dumps(s, indent=1))

# --- style / pipeline files ------------------------------------------------------------------------
d = target_dir("pipeline")
for f in sorted(os.listdir("stylize/presets")):
    if f.endswith(".json"):
        with open(os.path.join("stylize/presets", f)) as fh:
            p = json.load(fh)
        if "paper" in p and isinstance(p["paper"], dict):
            p["paper"]["file"] = "paper.png"
        put(d, f, json.dumps(p, indent=1))

# --- images ----------------------------------------------------------------------------------------
def png(w, h, color_type, bit_depth, pixel, plte=None):
    ch = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[color_type]
    bpc = bit_depth // 8 if bit_depth >= 8 else 1
    raw = b""
    for y in range(h):
        raw += b"\0" + b"".join(pixel(x, y) for x in range(w))
    def chunk(t, b):
        return struct.pack(">I", len(b)) + t + b + struct.pack(">I", zlib.crc32(t + b) & 0xffffffff)
    s = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bit_depth, color_type, 0, 0, 0))
    if plte:
        s += chunk(b"PLTE", plte)
    return s + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")

def bmp(w, h, bpp):
    pix = b""
    for y in range(h):
        row = b"".join(bytes([(x * 40) & 255, (y * 60) & 255, 128] + ([255] if bpp == 32 else [])) for x in range(w))
        pix += row + b"\0" * (-len(row) % 4)
    hdr = struct.pack("<IiiHHIIiiII", 40, w, h, 1, bpp, 0, len(pix), 2835, 2835, 0, 0)
    return b"BM" + struct.pack("<IHHI", 14 + len(hdr) + len(pix), 0, 0, 14 + len(hdr)) + hdr + pix

def tga(w, h, rle):
    hdr = struct.pack("<BBBHHBHHHHBB", 0, 0, 10 if rle else 2, 0, 0, 0, 0, 0, w, h, 32, 8)
    if rle:
        pix = b"".join(bytes([0x80 | (w - 1), 200, 100, 50, 255]) for _ in range(h))
    else:
        pix = b"".join(bytes([x * 30 & 255, y * 30 & 255, 90, 255]) for y in range(h) for x in range(w))
    return hdr + pix

def dds(w, h, fourcc=None, depth=0):
    # DDS_HEADER: size 124, flags CAPS|HEIGHT|WIDTH|PIXELFORMAT (+DEPTH), pixel format 32 bytes.
    flags = 0x1 | 0x2 | 0x4 | 0x1000 | (0x800000 if depth else 0)
    if fourcc:
        pf = struct.pack("<II4sIIIII", 32, 0x4, fourcc, 0, 0, 0, 0, 0)
        data = (b"\xff\xff\x00\x00\xaa\xaa\xaa\xaa" * ((w + 3) // 4) * ((h + 3) // 4))
    else:
        pf = struct.pack("<II4sIIIII", 32, 0x41, b"\0\0\0\0", 32, 0xff0000, 0xff00, 0xff, 0xff000000)
        data = bytes((i * 7) & 255 for i in range(w * h * 4))
    caps2 = 0x200000 if depth else 0
    hdr = struct.pack("<IIIIIII", 124, flags, h, w, 0, depth, 0) + b"\0" * 44 + pf + \
          struct.pack("<IIIII", 0x1000, caps2, 0, 0, 0)
    return b"DDS " + hdr + data * max(1, depth)

def hdr_rgbe(w, h):
    s = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w)
    return s + b"".join(bytes([128, (x * 20) & 255, 64, 129]) for _ in range(h) for x in range(w))

def pnm(w, h, kind):
    if kind == "P5":
        return b"P5\n%d %d\n255\n" % (w, h) + bytes((x * 30 + y) & 255 for y in range(h) for x in range(w))
    if kind == "P6":
        return b"P6\n%d %d\n255\n" % (w, h) + bytes((x * 30 + c * 70) & 255 for y in range(h) for x in range(w) for c in range(3))
    return b"P3\n%d %d\n255\n" % (w, h) + b" ".join(b"%d %d %d" % (x * 30, y * 30, 128) for y in range(h) for x in range(w)) + b"\n"

def pfm(w, h):
    return b"PF\n%d %d\n-1.0\n" % (w, h) + b"".join(struct.pack("<fff", x / w, y / h, 0.5) for y in range(h) for x in range(w))

d = target_dir("image")
put(d, "gray8.png", png(4, 4, 0, 8, lambda x, y: bytes([x * 60 + y])))
put(d, "gray16.png", png(3, 3, 0, 16, lambda x, y: struct.pack(">H", x * 20000 + y)))
put(d, "gray-alpha.png", png(4, 2, 4, 8, lambda x, y: bytes([x * 60, 255 - y * 100])))
put(d, "rgb.png", png(5, 3, 2, 8, lambda x, y: bytes([x * 50, y * 80, 128])))
put(d, "rgba16.png", png(2, 2, 6, 16, lambda x, y: struct.pack(">HHHH", x * 60000, y * 60000, 30000, 65535)))
put(d, "palette.png", png(4, 4, 3, 8, lambda x, y: bytes([(x + y) % 3]), plte=b"\xff\0\0\0\xff\0\0\0\xff"))
put(d, "rgb24.bmp", bmp(3, 2, 24))
put(d, "rgba32.bmp", bmp(2, 2, 32))
put(d, "rgba.tga", tga(3, 3, False))
put(d, "rle.tga", tga(4, 2, True))
put(d, "rgba.dds", dds(4, 4))
put(d, "dxt1.dds", dds(8, 4, b"DXT1"))
put(d, "rgbe.hdr", hdr_rgbe(4, 3))
put(d, "gray.pgm", pnm(4, 3, "P5"))
put(d, "rgb.ppm", pnm(3, 3, "P6"))
put(d, "ascii.ppm", pnm(2, 2, "P3"))
put(d, "float.pfm", pfm(2, 3))
for name, rel in [
    ("cube-metallic-roughness.png", "gltf/Cube/glTF/Cube_MetallicRoughness.png"),
    ("triangle-screenshot.png", "gltf/Triangle/screenshot/screenshot.png"),
    ("cesium-logo.png", "gltf/BoxTextured/CesiumLogoFlat.png"),
    ("box-screenshot.png", "gltf/Box/screenshot/screenshot.png"),
    ("cube-screenshot.jpg", "gltf/Cube/screenshot/screenshot.jpg"),
    ("suzanne-screenshot.jpg", "gltf/Suzanne/screenshot/screenshot.jpg"),
]:
    put(d, name, read(rel))
PY
echo "make_fuzz_corpus: seeds written to $out/ ($(du -sh "$out" | cut -f1))"
for t in "$out"/*/; do echo "  $(basename "$t"): $(ls "$t" | wc -l) files"; done
