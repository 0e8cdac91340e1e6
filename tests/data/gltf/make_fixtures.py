#!/usr/bin/env python3
"""Writes the glTF fixtures for tests/test_gltf_import.c into this folder.

Deterministic (no timestamps, fixed order); run it again after editing and
commit its output. Standard library only.
"""
import base64
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

FLOAT, USHORT = 5126, 5123


def png_rgb(width, height, rows):
    """A minimal 8-bit RGB PNG from rows of (r, g, b) tuples."""
    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data +
                struct.pack(">I", zlib.crc32(tag + data) & 0xffffffff))
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in rows)
    return (b"\x89PNG\r\n\x1a\n" +
            chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


# Top row red, green; bottom row blue, white.
TEXTURE_PNG = png_rgb(2, 2, [[(255, 0, 0), (0, 255, 0)], [(0, 0, 255), (255, 255, 255)]])


class Builder:
    """Collects one binary buffer with its bufferViews and accessors."""

    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def view(self, blob, stride=None):
        while len(self.data) % 4:
            self.data += b"\x00"
        self.views.append({"buffer": 0, "byteOffset": len(self.data), "byteLength": len(blob)})
        if stride:
            self.views[-1]["byteStride"] = stride
        self.data += blob
        return len(self.views) - 1

    def accessor(self, values, ncomp, ctype=FLOAT):
        fmt = "<f" if ctype == FLOAT else "<H"
        flat = [x for v in values for x in (v if ncomp > 1 else [v])]
        blob = b"".join(struct.pack(fmt, x) for x in flat)
        acc = {"bufferView": self.view(blob), "componentType": ctype,
               "count": len(values), "type": {1: "SCALAR", 2: "VEC2", 3: "VEC3"}[ncomp]}
        if ctype == FLOAT and ncomp == 3:
            finite = [v for v in values if all(math.isfinite(x) for x in v)]
            acc["min"] = [min(v[k] for v in finite) for k in range(3)]
            acc["max"] = [max(v[k] for v in finite) for k in range(3)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def gltf(self, doc, binary=False):
        """Completes `doc`; for GLB the buffer has no URI (it is the BIN chunk)."""
        doc["bufferViews"] = self.views
        doc["accessors"] = self.accessors
        buf = {"byteLength": len(self.data)}
        if not binary:
            buf["uri"] = ("data:application/octet-stream;base64," +
                          base64.b64encode(bytes(self.data)).decode())
        doc["buffers"] = [buf]
        return doc


def unit_triangle(b, indices=(0, 1, 2)):
    """Mesh primitive of the triangle (0,0,0) (1,0,0) (0,1,0), facing +Z."""
    return {"attributes": {
        "POSITION": b.accessor([(0, 0, 0), (1, 0, 0), (0, 1, 0)], 3),
        "NORMAL": b.accessor([(0, 0, 1)] * 3, 3),
        "TEXCOORD_0": b.accessor([(0, 0), (1, 0), (0, 1)], 2)},
        "indices": b.accessor(list(indices), 1, USHORT)}


S45 = math.sqrt(0.5)


def features(binary):
    """The main scene: transforms, hierarchy, camera, lights, materials, texture."""
    b = Builder()
    tri = unit_triangle(b)
    tri["material"] = 0
    plain = {"attributes": {"POSITION": b.accessor([(0, 0, -1), (1, 0, -1), (0, 1, -1)], 3)}}
    if binary:
        image = {"bufferView": b.view(TEXTURE_PNG), "mimeType": "image/png"}
    else:
        image = {"uri": "data:image/png;base64," + base64.b64encode(TEXTURE_PNG).decode()}
    nodes = [
        {"name": "trs", "mesh": 0, "translation": [1, 2, 3], "rotation": [0, 0, S45, S45],
         "scale": [2, 2, 2]},
        {"name": "matrix", "mesh": 0,
         "matrix": [0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1]},
        {"name": "parent", "translation": [0, 0, 10], "children": [3]},
        {"name": "child", "mesh": 0, "scale": [3, 3, 3], "children": [4]},
        {"name": "grandchild", "mesh": 0, "translation": [1, 0, 0]},
        {"name": "mirror", "mesh": 0, "scale": [-1, 1, 1]},
        {"name": "plain", "mesh": 1},
        {"name": "camera", "camera": 0, "translation": [0, 1, 5], "rotation": [0, S45, 0, S45]},
        {"name": "point", "translation": [0, 5, 0],
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "lights", "translation": [1, 0, 0], "children": [8, 10]},
        {"name": "spot", "translation": [0, 0, 2], "rotation": [S45, 0, 0, S45],
         "extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"name": "sun", "extensions": {"KHR_lights_punctual": {"light": 2}}},
    ]
    doc = {
        "asset": {"version": "2.0", "generator": "lvcl make_fixtures.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength",
                           "KHR_materials_transmission", "KHR_materials_ior",
                           "KHR_materials_specular", "KHR_materials_volume"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1, 0.5, 0.25], "intensity": 100},
            {"type": "spot", "intensity": 10,
             "spot": {"innerConeAngle": 0.25, "outerConeAngle": 0.5}},
            {"type": "directional", "name": "sun"},
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 5, 6, 7, 9, 11]}],
        "nodes": nodes,
        "meshes": [{"primitives": [tri]}, {"primitives": [plain]}],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1}}],
        "materials": [
            {"name": "glass", "doubleSided": True, "emissiveFactor": [1, 0.5, 0],
             "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.7, 1],
                                      "baseColorTexture": {"index": 0},
                                      "metallicFactor": 0, "roughnessFactor": 0.1},
             "extensions": {
                 "KHR_materials_emissive_strength": {"emissiveStrength": 4},
                 "KHR_materials_transmission": {"transmissionFactor": 0.75},
                 "KHR_materials_ior": {"ior": 1.33},
                 "KHR_materials_specular": {"specularFactor": 0.5},
                 "KHR_materials_volume": {"thicknessFactor": 0.1,
                                          "attenuationColor": [0.5, 0.6, 0.7],
                                          "attenuationDistance": 2.0}}},
            {"name": "plain"},
        ],
        "textures": [{"source": 0}],
        "images": [image],
    }
    return b.gltf(doc, binary), bytes(b.data)


def minimal(indices=(0, 1, 2)):
    """One indexed triangle in one node: the base for the broken files."""
    b = Builder()
    return b.gltf({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
                   "nodes": [{"mesh": 0}],
                   "meshes": [{"primitives": [unit_triangle(b, indices)]}]})


def nan_vertex():
    """Two triangles; the second uses a NaN vertex and must be skipped."""
    b = Builder()
    nan = float("nan")
    prim = {"attributes": {"POSITION": b.accessor(
        [(0, 0, 0), (1, 0, 0), (0, 1, 0), (nan, 0, 0)], 3)},
        "indices": b.accessor([0, 1, 2, 0, 2, 3], 1, USHORT)}
    return b.gltf({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}],
                   "nodes": [{"mesh": 0}], "meshes": [{"primitives": [prim]}]})


def sparse_strided():
    """Interleaved POSITION/NORMAL (stride 24), normalized ubyte UVs (stride 4)
    and a sparse accessor moving vertex 2 from (0,5,0) to (0,2,0)."""
    b = Builder()
    verts = [(0, 0, 0), (1, 0, 0), (0, 5, 0)]
    inter = b.view(b"".join(struct.pack("<6f", *v, 0, 0, 1) for v in verts), stride=24)
    uvs = b.view(bytes([0, 0, 0, 0, 255, 0, 0, 0, 0, 255, 0, 0]), stride=4)
    sp_idx = b.view(bytes([2]))
    sp_val = b.view(struct.pack("<3f", 0, 2, 0))
    b.accessors = [
        {"bufferView": inter, "componentType": FLOAT, "count": 3, "type": "VEC3",
         "min": [0, 0, 0], "max": [1, 5, 0],
         "sparse": {"count": 1, "indices": {"bufferView": sp_idx, "componentType": 5121},
                    "values": {"bufferView": sp_val}}},
        {"bufferView": inter, "byteOffset": 12, "componentType": FLOAT, "count": 3,
         "type": "VEC3"},
        {"bufferView": uvs, "componentType": 5121, "normalized": True, "count": 3,
         "type": "VEC2"},
    ]
    prim = {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}}
    return b.gltf({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}],
                   "nodes": [{"mesh": 0}], "meshes": [{"primitives": [prim]}]})


def glb(doc, bin_data):
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    bin_data = bytes(bin_data) + b"\x00" * (-len(bin_data) % 4)
    body = (struct.pack("<I4s", len(js), b"JSON") + js +
            struct.pack("<I4s", len(bin_data), b"BIN\x00") + bin_data)
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def write(name, content):
    if isinstance(content, dict):
        content = (json.dumps(content, indent=1) + "\n").encode()
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(content)


def mutated(fn):
    doc = minimal()
    fn(doc)
    return doc


def main():
    write("features.gltf", features(False)[0])
    # The same scene as GLB, with the buffer and the PNG in the BIN chunk.
    doc, bin_data = features(True)
    write("features.glb", glb(doc, bin_data))
    write("truncated.glb", glb(doc, bin_data)[:600])
    write("nan_vertex.gltf", nan_vertex())
    write("sparse_strided.gltf", sparse_strided())
    write("malformed.gltf", b'{"asset": {"version": "2.0"}, "nodes": [{"mesh": 0}\n')
    write("bad_buffer_index.gltf",
          mutated(lambda d: d["bufferViews"][0].update(buffer=5)))
    write("accessor_past_end.gltf",
          mutated(lambda d: d["accessors"][0].update(count=1000)))
    write("bad_bufferview_index.gltf",
          mutated(lambda d: d["accessors"][0].update(bufferView=9)))
    write("bad_index_value.gltf", minimal(indices=[0, 1, 7]))
    write("node_cycle.gltf",
          mutated(lambda d: d.update(nodes=[{"children": [1]}, {"mesh": 0, "children": [0]}])))
    write("draco_required.gltf",
          mutated(lambda d: d.update(extensionsUsed=["KHR_draco_mesh_compression"],
                                     extensionsRequired=["KHR_draco_mesh_compression"])))
    write("no_triangles.gltf", mutated(lambda d: d["nodes"][0].pop("mesh")))


if __name__ == "__main__":
    main()
