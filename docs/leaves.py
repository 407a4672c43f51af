"""Write leaves.gltf: 400 leaf cards cut out of quads by a texture's alpha (alphaMode MASK) over a
ground, no camera and no light (beam's defaults), and leaves-opaque.gltf, the same quads opaque.
The cut-out content of docs/benchmarks.md. Standard library only."""
import base64, json, math, random, struct, zlib

W = 32
rows = b""
for y in range(W):
    rows += b"\0"
    for x in range(W):
        u, v = (x + 0.5) / W * 2 - 1, (y + 0.5) / W * 2 - 1
        rows += bytes([60, 140, 50, 255 if u * u + v * v / 0.35 < 0.9 and abs(v) < 0.75 else 0])
chunk = lambda kind, data: struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, W, 8, 6, 0, 0, 0))
png += chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")

random.seed(3)
pos, uv, idx = [], [], []
for _ in range(400):
    c = [random.uniform(-1.5, 1.5), random.uniform(1.5, 3.0), random.uniform(-1.5, 1.5)]
    th, ph = random.uniform(0, math.pi), random.uniform(-1, 1)
    a = [0.25 * math.cos(th), 0.075 * ph, 0.25 * math.sin(th)]
    b = [-0.12 * math.sin(th) * ph, 0.12, 0.12 * math.cos(th)]
    base = len(pos)
    for s, t in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
        pos.append([c[i] + s * a[i] + t * b[i] for i in range(3)])
        uv.append([(s + 1) / 2, (1 - t) / 2])
    idx += [base, base + 1, base + 2, base, base + 2, base + 3]
g = len(pos)
pos += [[-6, 0, -6], [-6, 0, 6], [6, 0, 6], [6, 0, -6]]
uv += [[0, 0]] * 4
ground = [g, g + 1, g + 2, g, g + 2, g + 3]

parts = [
    b"".join(struct.pack("<3f", *p) for p in pos),
    b"".join(struct.pack("<2f", *t) for t in uv),
    b"".join(struct.pack("<I", i) for i in idx),
    b"".join(struct.pack("<I", i) for i in ground),
]
views, at = [], 0
for p in parts:
    views.append({"buffer": 0, "byteOffset": at, "byteLength": len(p)})
    at += len(p)
data = b"".join(parts)
lo = [min(p[i] for p in pos) for i in range(3)]
hi = [max(p[i] for p in pos) for i in range(3)]
doc = {
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [
        {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0},
        {"attributes": {"POSITION": 0}, "indices": 3, "material": 1},
    ]}],
    "materials": [
        {"alphaMode": "MASK", "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1], "metallicFactor": 0}},
    ],
    "images": [{"uri": "data:image/png;base64," + base64.b64encode(png).decode()}],
    "samplers": [{"magFilter": 9728}],
    "textures": [{"source": 0, "sampler": 0}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
        {"bufferView": 1, "componentType": 5126, "count": len(uv), "type": "VEC2"},
        {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
        {"bufferView": 3, "componentType": 5125, "count": len(ground), "type": "SCALAR"},
    ],
    "bufferViews": views,
    "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode(),
                 "byteLength": len(data)}],
}
json.dump(doc, open("leaves.gltf", "w"))
doc["materials"][0] = {"doubleSided": True,
                       "pbrMetallicRoughness": {"baseColorFactor": [0.24, 0.55, 0.2, 1], "metallicFactor": 0}}
json.dump(doc, open("leaves-opaque.gltf", "w"))
