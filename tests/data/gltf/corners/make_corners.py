#!/usr/bin/env python3
"""Writes the glTF specification's corner cases for tests/scene/test_gltf_corners.c.

Every quad_* file encodes the same unit square (0,0,0)-(1,1,0), facing +Z
as two triangles, through a different feature of the specification (index
widths, strips and fans, interleaving, sparse accessors without a buffer
view, quantized attributes, hierarchies, instancing, scenes, buffer URIs,
GLB chunk layouts), so each must import to exactly that square. The bad_*
files must be refused with one line. cases.txt lists every file with what
it must give: "ok" (and optionally a warning it must print) or an error
code and a fragment of the message. Deterministic; standard library only;
run it again after editing and commit its output.
"""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

BYTE, UBYTE, SHORT, USHORT, UINT, FLOAT = 5120, 5121, 5122, 5123, 5125, 5126
FORMAT = {BYTE: "b", UBYTE: "B", SHORT: "h", USHORT: "H", UINT: "I", FLOAT: "f"}
TYPES = {1: "SCALAR", 2: "VEC2", 3: "VEC3"}
TRIANGLES, POINTS, LINES, STRIP, FAN = 4, 0, 1, 5, 6

# The square's corners, its two triangles (counter-clockwise seen from +Z).
SQUARE = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
LIST = [0, 1, 2, 0, 2, 3]


class Doc:
    """One glTF document with one binary buffer."""

    def __init__(self):
        self.data = bytearray()
        self.json = {"asset": {"version": "2.0", "generator": "lvcl make_corners.py"},
                     "bufferViews": [], "accessors": [], "meshes": [], "nodes": []}

    def view(self, blob, stride=None, target=None):
        while len(self.data) % 4:
            self.data += b"\x00"
        v = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(blob)}
        if stride:
            v["byteStride"] = stride
        if target:
            v["target"] = target
        self.json["bufferViews"].append(v)
        self.data += blob
        return len(self.json["bufferViews"]) - 1

    def add_accessor(self, acc):
        self.json["accessors"].append(acc)
        return len(self.json["accessors"]) - 1

    def accessor(self, values, ncomp, ctype=FLOAT, normalized=False):
        flat = [x for v in values for x in (v if ncomp > 1 else [v])]
        blob = struct.pack("<%d%s" % (len(flat), FORMAT[ctype]), *flat)
        acc = {"bufferView": self.view(blob), "componentType": ctype,
               "count": len(values), "type": TYPES[ncomp]}
        if normalized:
            acc["normalized"] = True
        if ncomp == 3 and ctype == FLOAT:
            acc["min"] = [min(v[k] for v in values) for k in range(3)]
            acc["max"] = [max(v[k] for v in values) for k in range(3)]
        return self.add_accessor(acc)

    def mesh(self, *primitives):
        self.json["meshes"].append({"primitives": list(primitives)})
        return len(self.json["meshes"]) - 1

    def node(self, **fields):
        self.json["nodes"].append(fields)
        return len(self.json["nodes"]) - 1

    def scene(self, roots):
        self.json["scenes"] = [{"nodes": roots}]
        self.json["scene"] = 0

    def finish(self, uri="base64"):
        """The JSON with its buffer as a data URI ("base64"), as the URI given,
        or without one (None: a GLB's BIN chunk). Without materials of its
        own, every primitive glows white, so renders of the encodings can
        be compared."""
        if "materials" not in self.json:
            self.json["materials"] = [{"emissiveFactor": [1, 1, 1]}]
            for mesh in self.json["meshes"]:
                for prim in mesh["primitives"]:
                    prim["material"] = 0
        buf = {"byteLength": len(self.data)}
        if uri == "base64":
            buf["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bytes(self.data)).decode()
        elif uri is not None:
            buf["uri"] = uri
        self.json["buffers"] = [buf]
        return self.json


def square_attributes(d, order=SQUARE):
    """POSITION, NORMAL and TEXCOORD_0 (u, v = x, y) of the vertices `order`."""
    return {"POSITION": d.accessor(order, 3),
            "NORMAL": d.accessor([(0, 0, 1)] * len(order), 3),
            "TEXCOORD_0": d.accessor([(x, y) for x, y, _ in order], 2)}


def square(d, index_type=USHORT, **extra):
    prim = {"attributes": square_attributes(d), "indices": d.accessor(LIST, 1, index_type)}
    prim.update(extra)
    return prim


def single_node(d, prim):
    d.scene([d.node(mesh=d.mesh(prim))])
    return d


# ---- quads: each must import to the square ----

def quad_indices(index_type):
    d = Doc()
    return single_node(d, square(d, index_type)).finish()


def quad_unindexed():
    d = Doc()
    corners = [SQUARE[i] for i in LIST]
    return single_node(d, {"attributes": square_attributes(d, corners)}).finish()


def quad_strip(indexed):
    # Triangle i of a strip is (v_i, v_{i+1+i%2}, v_{i+2-i%2}): the order
    # below gives (3,0,2) then (0,1,2) of the square, both counter-clockwise.
    d = Doc()
    order = [SQUARE[3], SQUARE[0], SQUARE[2], SQUARE[1]]
    if indexed:
        prim = {"attributes": square_attributes(d), "indices": d.accessor([3, 0, 2, 1], 1, UBYTE)}
    else:
        prim = {"attributes": square_attributes(d, order)}
    prim["mode"] = STRIP
    return single_node(d, prim).finish()


def quad_fan():
    # Triangle i of a fan is (v_{i+1}, v_{i+2}, v_0).
    d = Doc()
    return single_node(d, {"attributes": square_attributes(d), "mode": FAN}).finish()


def quad_interleaved():
    """POSITION, NORMAL and TEXCOORD_0 in one view (stride 32), behind a
    view that starts mid-buffer and accessors with byte offsets."""
    d = Doc()
    d.view(b"\xee" * 20)  # unrelated bytes before the vertex view
    blob = b"".join(struct.pack("<8f", x, y, z, 0, 0, 1, x, y) for x, y, z in SQUARE)
    v = d.view(blob, stride=32, target=34962)
    pos = d.add_accessor({"bufferView": v, "componentType": FLOAT, "count": 4, "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0]})
    nrm = d.add_accessor({"bufferView": v, "byteOffset": 12, "componentType": FLOAT, "count": 4, "type": "VEC3"})
    uv = d.add_accessor({"bufferView": v, "byteOffset": 24, "componentType": FLOAT, "count": 4, "type": "VEC2"})
    idx_view = d.view(struct.pack("<8H", 9, 9, *LIST), target=34963)
    idx = d.add_accessor({"bufferView": idx_view, "byteOffset": 4, "componentType": USHORT, "count": 6,
                          "type": "SCALAR"})
    prim = {"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}, "indices": idx}
    return single_node(d, prim).finish()


def quad_sparse_zeros():
    """POSITION with no bufferView (all zeros) and a sparse substitution of
    vertices 1..3; vertex 0 stays at the zero the specification gives it."""
    d = Doc()
    sp_idx = d.view(struct.pack("<3H", 1, 2, 3))
    sp_val = d.view(struct.pack("<9f", *[c for v in SQUARE[1:] for c in v]))
    pos = d.add_accessor({"componentType": FLOAT, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0],
                          "sparse": {"count": 3, "indices": {"bufferView": sp_idx, "componentType": USHORT},
                                     "values": {"bufferView": sp_val}}})
    prim = {"attributes": {"POSITION": pos}, "indices": d.accessor(LIST, 1, UBYTE)}
    return single_node(d, prim).finish()


def quad_quantized(position_type, normalized_positions):
    """KHR_mesh_quantization: integer positions undone by the node's scale,
    byte normals, normalized unsigned short UVs."""
    d = Doc()
    d.json["extensionsUsed"] = ["KHR_mesh_quantization"]
    d.json["extensionsRequired"] = ["KHR_mesh_quantization"]
    q = {SHORT: 32767, USHORT: 65535, BYTE: 127, UBYTE: 255}[position_type] if normalized_positions else 1000
    pos = d.accessor([(x * q, y * q, z * q) for x, y, z in SQUARE], 3, position_type, normalized_positions)
    d.json["accessors"][pos].update(min=[0, 0, 0], max=[q, q, 0])
    nrm = d.accessor([(0, 0, 127)] * 4, 3, BYTE, True)
    uv = d.accessor([(x * 65535, y * 65535) for x, y, _ in SQUARE], 2, USHORT, True)
    prim = {"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}, "indices": d.accessor(LIST, 1, UBYTE)}
    node = {"mesh": d.mesh(prim)}
    if not normalized_positions:
        node["scale"] = [1 / q] * 3
    d.scene([d.node(**node)])
    return d.finish()


def quad_hierarchy():
    """Two levels whose transforms cancel: T(2,3,4) S(2), then T(-1,-1.5,-2)
    S(0.5) given as a matrix, then a rotation by 360 degrees."""
    d = Doc()
    mesh = d.mesh(square(d))
    leaf = d.node(mesh=mesh, rotation=[0, 0, 1, 0])  # 180 degrees about Z ...
    mid = d.node(children=[d.node(children=[leaf], rotation=[0, 0, 1, 0])],  # ... twice
                 matrix=[0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, -1, -1.5, -2, 1])
    d.scene([d.node(children=[mid], translation=[2, 3, 4], scale=[2, 2, 2])])
    return d.finish()


def quad_instanced():
    """One triangle mesh placed twice: as is, and turned 180 degrees about
    the square's centre by a matrix, onto its other half (no UVs: they
    would not follow x, y there)."""
    d = Doc()
    tri = [SQUARE[0], SQUARE[1], SQUARE[2]]
    mesh = d.mesh({"attributes": {"POSITION": d.accessor(tri, 3), "NORMAL": d.accessor([(0, 0, 1)] * 3, 3)}})
    d.scene([d.node(mesh=mesh), d.node(mesh=mesh, matrix=[-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0, 1, 1, 0, 1])])
    return d.finish()


def quad_scenes():
    """The default scene is scene 1; scene 0 holds a triangle far away."""
    d = Doc()
    far = d.node(mesh=d.mesh({"attributes": {"POSITION": d.accessor([(9, 9, 9), (10, 9, 9), (9, 10, 9)], 3)}}))
    near = d.node(mesh=d.mesh(square(d)))
    d.json["scenes"] = [{"nodes": [far]}, {"nodes": [near]}]
    d.json["scene"] = 1
    return d.finish()


def quad_no_scene():
    """No scenes: every root node is drawn; a child once, under its parent."""
    d = Doc()
    child = d.node(mesh=d.mesh(square(d)))
    d.node(children=[child])
    return d.finish()


def quad_with_points_and_lines():
    """Point and line primitives beside the square: skipped with a warning."""
    d = Doc()
    pts = d.accessor(SQUARE, 3)
    d.scene([d.node(mesh=d.mesh(square(d), {"attributes": {"POSITION": pts}, "mode": POINTS},
                                {"attributes": {"POSITION": pts}, "mode": LINES}))])
    return d.finish()


def quad_gltf_buffer_mime():
    """A data URI of type application/gltf-buffer (the other one allowed)."""
    d = Doc()
    doc = single_node(d, square(d)).finish()
    doc["buffers"][0]["uri"] = doc["buffers"][0]["uri"].replace("application/octet-stream", "application/gltf-buffer")
    return doc


def quad_external(uri):
    d = Doc()
    return single_node(d, square(d)).finish(uri), bytes(d.data)


def quad_texcoord_1():
    """The base colour texture reads TEXCOORD_1 (texCoord 1); TEXCOORD_0 is
    something else."""
    d = Doc()
    attrs = square_attributes(d)
    attrs["TEXCOORD_1"] = attrs["TEXCOORD_0"]
    attrs["TEXCOORD_0"] = d.accessor([(0.5, 0.5)] * 4, 2)
    png = base64.b64decode("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR4nGP4z8AAAAMBAQDJ/pLvAAAAAElFTkSuQmCC")
    d.json["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(png).decode()}]
    d.json["textures"] = [{"source": 0}]
    d.json["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}}]
    prim = {"attributes": attrs, "indices": d.accessor(LIST, 1, USHORT), "material": 0}
    return single_node(d, prim).finish()


def quad_camera_without_aspect():
    """A perspective camera with no aspectRatio: the image's is used."""
    d = Doc()
    d.json["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.01}},
                         {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0, "zfar": 9}}]
    d.scene([d.node(mesh=d.mesh(square(d))), d.node(camera=1, translation=[0.5, 0.5, 3]),
             d.node(camera=0, translation=[0.5, 0.5, 3])])
    return d.finish()


# ---- GLB layouts ----

def chunk(kind, payload, pad):
    payload = bytes(payload) + pad * (-len(payload) % 4)
    return struct.pack("<I4s", len(payload), kind) + payload


def glb(doc, bin_data=None, extra_bin=b"", chunks_after=b""):
    body = chunk(b"JSON", json.dumps(doc, separators=(",", ":")).encode(), b" ")
    if bin_data is not None:
        body += chunk(b"BIN\x00", bytes(bin_data) + extra_bin, b"\x00")
    body += chunks_after
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def square_doc(uri=None):
    d = Doc()
    single_node(d, square(d))
    return d.finish(uri), bytes(d.data)


def main():
    cases = []

    def case(name, content, expect):
        if isinstance(content, dict):
            content = (json.dumps(content, indent=1) + "\n").encode()
        with open(os.path.join(HERE, name), "wb") as f:
            f.write(content)
        cases.append("%s %s" % (name, expect))

    def side_file(name, content):
        path = os.path.join(HERE, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(content)

    case("quad_indices_u8.gltf", quad_indices(UBYTE), "ok")
    case("quad_indices_u16.gltf", quad_indices(USHORT), "ok")
    case("quad_indices_u32.gltf", quad_indices(UINT), "ok")
    case("quad_unindexed.gltf", quad_unindexed(), "ok")
    case("quad_strip.gltf", quad_strip(False), "ok")
    case("quad_strip_indexed.gltf", quad_strip(True), "ok")
    case("quad_fan.gltf", quad_fan(), "ok")
    case("quad_interleaved.gltf", quad_interleaved(), "ok")
    case("quad_sparse_zeros.gltf", quad_sparse_zeros(), "ok")
    case("quad_quantized_short.gltf", quad_quantized(SHORT, False), "ok")
    case("quad_quantized_ubyte_normalized.gltf", quad_quantized(UBYTE, True), "ok")
    case("quad_quantized_short_normalized.gltf", quad_quantized(SHORT, True), "ok")
    case("quad_hierarchy.gltf", quad_hierarchy(), "ok")
    case("quad_instanced.gltf", quad_instanced(), "ok")
    case("quad_scenes.gltf", quad_scenes(), "ok")
    case("quad_no_scene.gltf", quad_no_scene(), "ok")
    case("quad_with_points_and_lines.gltf", quad_with_points_and_lines(), "ok warning=no surface")
    case("quad_gltf_buffer_mime.gltf", quad_gltf_buffer_mime(), "ok")
    case("quad_texcoord_1.gltf", quad_texcoord_1(), "ok")
    case("quad_camera_without_aspect.gltf", quad_camera_without_aspect(), "ok warning=orthographic")
    doc, data = quad_external("quad%20data.bin")
    side_file("quad data.bin", data)
    case("quad_external_escaped_uri.gltf", doc, "ok")
    doc, data = quad_external("buffers/quad.bin")
    side_file("buffers/quad.bin", data)
    case("quad_external_subfolder.gltf", doc, "ok")

    doc, data = square_doc()
    case("quad_glb.glb", glb(doc, data), "ok")
    # Clients must skip chunks of unknown type.
    case("quad_glb_unknown_chunk.glb", glb(doc, data, chunks_after=chunk(b"XTRA", b"ignore me", b"\x00")), "ok")
    # The BIN chunk may be up to 3 bytes longer than the buffer.
    odd = Doc()
    single_node(odd, {"attributes": {"POSITION": odd.accessor([SQUARE[i] for i in LIST], 3)}})
    odd.view(b"\x01")  # the buffer ends one byte past a multiple of 4
    case("quad_glb_padded_bin.glb", glb(odd.finish(None), odd.data), "ok")
    # No BIN chunk: the buffer is a data URI.
    doc_uri, _ = square_doc("base64")
    case("quad_glb_no_bin.glb", glb(doc_uri), "ok")
    # BIN chunk present but the buffer is an external file.
    doc_ext, data = quad_external("buffers/quad.bin")
    case("quad_glb_external_buffer.glb", glb(doc_ext), "ok")

    # ---- refused, with one line ----
    q = quad_quantized(SHORT, False)
    q.pop("extensionsUsed")
    q.pop("extensionsRequired")
    case("bad_quantized_undeclared.gltf", q, "parse KHR_mesh_quantization")
    doc, _ = quad_external("missing.bin")
    case("bad_missing_buffer.gltf", doc, "io missing.bin")
    doc, _ = quad_external("http://example.com/quad.bin")
    case("bad_remote_buffer.gltf", doc, "unsupported http://example.com/quad.bin")
    doc, data = square_doc()
    case("bad_glb_short_bin.glb", glb(doc, data[:-8]), "parse byteLength")
    whole = glb(doc, data)
    case("bad_glb_chunk_past_end.glb", whole[:12] + struct.pack("<I", 1 << 20) + whole[16:], "parse runs past the end")
    case("bad_glb_bin_first.glb",
         struct.pack("<4sII", b"glTF", 2, 12 + len(chunk(b"BIN\x00", data, b"\x00"))) + chunk(b"BIN\x00", data, b"\x00"),
         "parse not JSON")
    case("bad_glb_version_1.glb", b"glTF" + struct.pack("<I", 1) + whole[8:], "unsupported version 1")
    doc, _ = square_doc("data:application/octet-stream;base64,@@@@not-base64@@@@")
    case("bad_data_uri.gltf", doc, "parse base64")
    d = Doc()
    single_node(d, square(d))
    old = d.finish()
    old["asset"]["version"] = "1.0"
    case("bad_gltf_1.gltf", old, "unsupported version 1.0")
    d = Doc()
    single_node(d, {"attributes": square_attributes(d), "indices": d.accessor(LIST, 1, FLOAT)})
    case("bad_float_indices.gltf", d.finish(), "parse indices")
    d = Doc()
    single_node(d, {"attributes": {"POSITION": d.accessor(SQUARE[:2], 3)}, "mode": STRIP})
    case("bad_strip_too_short.gltf", d.finish(), "unsupported no triangles")
    mesh_gpu = Doc()
    single_node(mesh_gpu, square(mesh_gpu))
    gpu = mesh_gpu.finish()
    gpu["extensionsUsed"] = gpu["extensionsRequired"] = ["EXT_meshopt_compression"]
    case("bad_meshopt_required.gltf", gpu, "unsupported EXT_meshopt_compression")

    with open(os.path.join(HERE, "cases.txt"), "w") as f:
        f.write("# file  expectation (written by make_corners.py)\n")
        f.write("\n".join(cases) + "\n")


if __name__ == "__main__":
    main()
