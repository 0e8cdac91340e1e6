#!/usr/bin/env python3
"""Convert a glTF 2.0 scene (.gltf or .glb) to a Mitsuba 3 scene dictionary
following lvcl's material contract (docs/design.md, "Scene conventions").  See README.md in
this directory for the rules and the known mismatches.

Library use:
    import gltf_to_mitsuba as g2m
    scene_dict, info = g2m.convert("scene.gltf", width=256, height=256,
                                   spp=64, workdir="/tmp/somewhere")
    scene = mi.load_dict(scene_dict)      # after mi.set_variant(...)

Command line (prints a JSON summary of the conversion):
    gltf_to_mitsuba.py SCENE [--width W] [--height H]

glTF reading is done here with json + numpy (GLB container, data URIs and
external .bin/image files).  Geometry is baked to world space and written as
binary PLY files into `workdir` (Mitsuba's native mesh loader); meshes used by
more than one node and carrying no emitter become a shapegroup + instances.
"""

import argparse
import base64
import json
import math
import os
import struct
import sys
import tempfile
import urllib.parse

import numpy as np

# --------------------------------------------------------------------- glTF I/O

GLB_MAGIC = 0x46546C67
CHUNK_JSON = 0x4E4F534A
CHUNK_BIN = 0x004E4942

COMPONENT = {5120: np.int8, 5121: np.uint8, 5122: np.int16,
             5123: np.uint16, 5125: np.uint32, 5126: np.float32}
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4,
         "MAT2": 4, "MAT3": 9, "MAT4": 16}


class GltfError(Exception):
    pass


def _read_uri(uri, base_dir):
    if uri.startswith("data:"):
        head, _, data = uri.partition(",")
        if head.endswith(";base64"):
            return base64.b64decode(data)
        return urllib.parse.unquote_to_bytes(data)
    path = os.path.join(base_dir, urllib.parse.unquote(uri))
    if not os.path.exists(path):
        raise GltfError("missing external file: %s" % path)
    with open(path, "rb") as f:
        return f.read()


class Gltf:
    def __init__(self, path):
        self.path = path
        self.base_dir = os.path.dirname(os.path.abspath(path))
        with open(path, "rb") as f:
            data = f.read()
        glb_bin = None
        if len(data) >= 12 and struct.unpack_from("<I", data, 0)[0] == GLB_MAGIC:
            _, version, length = struct.unpack_from("<III", data, 0)
            if version != 2:
                raise GltfError("unsupported GLB version %d" % version)
            off, doc = 12, None
            while off + 8 <= min(length, len(data)):
                clen, ctype = struct.unpack_from("<II", data, off)
                chunk = data[off + 8: off + 8 + clen]
                if ctype == CHUNK_JSON:
                    doc = json.loads(chunk.decode("utf-8"))
                elif ctype == CHUNK_BIN and glb_bin is None:
                    glb_bin = chunk
                off += 8 + clen + ((4 - clen % 4) % 4)
            if doc is None:
                raise GltfError("GLB without a JSON chunk")
        else:
            doc = json.loads(data.decode("utf-8"))
        self.doc = doc
        if doc.get("asset", {}).get("version", "2.0")[:1] != "2":
            raise GltfError("not a glTF 2.0 file")
        for ext in doc.get("extensionsRequired", []):
            if ext not in SUPPORTED_EXTENSIONS:
                raise GltfError("required extension not supported: %s" % ext)
        self.buffers = []
        for i, b in enumerate(doc.get("buffers", [])):
            if "uri" in b:
                self.buffers.append(_read_uri(b["uri"], self.base_dir))
            elif i == 0 and glb_bin is not None:
                self.buffers.append(glb_bin)
            else:
                raise GltfError("buffer %d has no data" % i)

    def view_bytes(self, vi):
        v = self.doc["bufferViews"][vi]
        buf = self.buffers[v["buffer"]]
        off = v.get("byteOffset", 0)
        return buf[off: off + v["byteLength"]], v.get("byteStride")

    def accessor(self, ai):
        a = self.doc["accessors"][ai]
        dtype = np.dtype(COMPONENT[a["componentType"]]).newbyteorder("<")
        ncomp = NCOMP[a["type"]]
        count = a["count"]
        if "bufferView" in a:
            raw, stride = self.view_bytes(a["bufferView"])
            off = a.get("byteOffset", 0)
            elem = dtype.itemsize * ncomp
            stride = stride or elem
            if stride == elem:
                arr = np.frombuffer(raw, dtype=dtype, count=count * ncomp,
                                    offset=off).reshape(count, ncomp)
            else:
                arr = np.lib.stride_tricks.as_strided(
                    np.frombuffer(raw, dtype=np.uint8, offset=off),
                    shape=(count, elem), strides=(stride, 1))
                arr = np.ascontiguousarray(arr).view(dtype).reshape(count, ncomp)
        else:
            arr = np.zeros((count, ncomp), dtype=dtype)
        arr = arr.copy()
        if "sparse" in a:
            sp = a["sparse"]
            ii = sp["indices"]
            raw, _ = self.view_bytes(ii["bufferView"])
            idx = np.frombuffer(raw, dtype=np.dtype(COMPONENT[ii["componentType"]]).newbyteorder("<"),
                                count=sp["count"], offset=ii.get("byteOffset", 0))
            vv = sp["values"]
            raw, _ = self.view_bytes(vv["bufferView"])
            vals = np.frombuffer(raw, dtype=dtype, count=sp["count"] * ncomp,
                                 offset=vv.get("byteOffset", 0)).reshape(-1, ncomp)
            arr[idx.astype(np.int64)] = vals
        if a.get("normalized", False) and dtype.kind in "iu":
            info = np.iinfo(dtype)
            arr = np.maximum(arr.astype(np.float64) / info.max, -1.0)
        return arr

    def image_bytes(self, ii):
        im = self.doc["images"][ii]
        if "uri" in im:
            data = _read_uri(im["uri"], self.base_dir)
        else:
            data, _ = self.view_bytes(im["bufferView"])
        mime = im.get("mimeType", "")
        if not mime:
            mime = "image/png" if data[:4] == b"\x89PNG" else "image/jpeg"
        return bytes(data), mime


SUPPORTED_EXTENSIONS = {
    "KHR_materials_specular", "KHR_materials_emissive_strength",
    "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
    "KHR_lights_punctual", "KHR_mesh_quantization", "KHR_texture_transform",
}


# --------------------------------------------------------------------- transforms

def quat_to_mat3(q):
    x, y, z, w = q
    n = math.sqrt(x * x + y * y + z * z + w * w) or 1.0
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def node_local_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # column-major
    m = np.eye(4)
    t = node.get("translation", [0.0, 0.0, 0.0])
    r = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    s = node.get("scale", [1.0, 1.0, 1.0])
    m[:3, :3] = quat_to_mat3(r) @ np.diag(s)
    m[:3, 3] = t
    return m


def walk_nodes(doc):
    """Yield (node_index, world_matrix) for every node of the default scene."""
    scenes = doc.get("scenes", [])
    if scenes:
        roots = scenes[doc.get("scene", 0)].get("nodes", [])
    else:  # no scene: every node that is nobody's child is a root
        children = {c for n in doc.get("nodes", []) for c in n.get("children", [])}
        roots = [i for i in range(len(doc.get("nodes", []))) if i not in children]
    stack = [(r, np.eye(4), 0) for r in reversed(roots)]
    while stack:
        ni, parent, depth = stack.pop()
        if depth > 256:
            raise GltfError("node hierarchy too deep (cycle?)")
        node = doc["nodes"][ni]
        world = parent @ node_local_matrix(node)
        yield ni, world
        for c in reversed(node.get("children", [])):
            stack.append((c, world, depth + 1))


# --------------------------------------------------------------------- materials

def _rgb(v):
    return {"type": "rgb", "value": [float(c) for c in v[:3]]}


def material_info(doc, mi_index):
    """Normalised view of one glTF material (defaults per the spec)."""
    if mi_index is None:
        mat = {}
    else:
        mat = doc["materials"][mi_index]
    pbr = mat.get("pbrMetallicRoughness", {})
    ext = mat.get("extensions", {})
    spec = ext.get("KHR_materials_specular", {})
    trans = ext.get("KHR_materials_transmission", {})
    vol = ext.get("KHR_materials_volume")
    em = ext.get("KHR_materials_emissive_strength", {})
    info = {
        "name": mat.get("name") or ("material%d" % mi_index if mi_index is not None
                                    else "default"),
        "base": [float(c) for c in pbr.get("baseColorFactor", [1, 1, 1, 1])][:3],
        "base_tex": pbr.get("baseColorTexture"),
        "metallic": float(pbr.get("metallicFactor", 1.0)),
        "roughness": float(pbr.get("roughnessFactor", 1.0)),
        "specular": float(spec.get("specularFactor", 1.0)),
        "specular_color": [float(c) for c in spec.get("specularColorFactor", [1, 1, 1])],
        "transmission": float(trans.get("transmissionFactor", 0.0)),
        "thickness": float(vol.get("thicknessFactor", 0.0)) if vol else 0.0,
        "att_color": [float(c) for c in (vol or {}).get("attenuationColor", [1, 1, 1])],
        "att_dist": float((vol or {}).get("attenuationDistance", math.inf)),
        "ior": float(ext.get("KHR_materials_ior", {}).get("ior", 1.5)),
        "double_sided": bool(mat.get("doubleSided", False)),
        "emission": [float(c) * float(em.get("emissiveStrength", 1.0))
                     for c in mat.get("emissiveFactor", [0, 0, 0])],
    }
    if pbr.get("metallicRoughnessTexture") or mat.get("emissiveTexture") \
            or trans.get("transmissionTexture"):
        info["warn"] = "textures other than baseColorTexture are ignored"
    return info


def classify(m):
    if m["transmission"] > 0.0 and m["metallic"] < 1.0:
        return "solid_dielectric" if m["thickness"] > 0.0 else "thin_dielectric"
    if m["metallic"] >= 1.0:
        if m["roughness"] == 0.0 and all(c >= 1.0 for c in m["base"]) and not m["base_tex"]:
            return "mirror"
        return "conductor"
    if m["metallic"] <= 0.0 and m["specular"] == 0.0:
        return "lambert"
    if m["metallic"] <= 0.0:
        return "plastic"
    return "mixed_metal"


class Converter:
    def __init__(self, gltf, workdir):
        self.g = gltf
        self.workdir = workdir
        self.textures = {}
        self.notes = []

    def note(self, msg):
        if msg not in self.notes:
            self.notes.append(msg)

    def base_color(self, m):
        """Mitsuba texture (or rgb) of baseColor x baseColorTexture."""
        if not m["base_tex"]:
            return _rgb(m["base"])
        ti = m["base_tex"]["index"]
        if m["base_tex"].get("texCoord", 0) != 0:
            self.note("baseColorTexture uses TEXCOORD_%d; TEXCOORD_0 used instead"
                      % m["base_tex"]["texCoord"])
        key = (ti, tuple(m["base"]))
        if key not in self.textures:
            self.textures[key] = self._load_texture(ti, m["base"])
        transform = m["base_tex"].get("extensions", {}).get("KHR_texture_transform")
        if not transform:
            return self.textures[key]
        # KHR_texture_transform: UVs scaled, turned, then offset (the
        # ratified matrix); Mitsuba's bitmap reads glTF's UVs unchanged.
        import mitsuba as mi
        sx, sy = transform.get("scale", [1.0, 1.0])
        ox, oy = transform.get("offset", [0.0, 0.0])
        r = transform.get("rotation", 0.0)
        c, s = math.cos(r), math.sin(r)
        matrix = mi.ScalarMatrix3f([[c * sx, s * sy, ox], [-s * sx, c * sy, oy], [0.0, 0.0, 1.0]])
        return dict(self.textures[key], to_uv=mi.ScalarTransform3f(matrix))

    def _load_texture(self, ti, factor):
        import mitsuba as mi
        doc = self.g.doc
        tex = doc["textures"][ti]
        data, mime = self.g.image_bytes(tex["source"])
        ext = ".png" if "png" in mime else ".jpg"
        path = os.path.join(self.workdir, "tex%d%s" % (ti, ext))
        with open(path, "wb") as f:
            f.write(data)
        bmp = mi.Bitmap(path)
        # glTF base colour textures are sRGB encoded: convert to linear float.
        bmp = bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False)
        arr = np.array(bmp, copy=True).reshape(bmp.height(), bmp.width(), 3)
        arr *= np.asarray(factor, dtype=np.float32)[None, None, :]
        lin = os.path.join(self.workdir, "tex%d_%d.exr" % (ti, len(self.textures)))
        mi.Bitmap(arr.astype(np.float32)).write(lin)
        sampler = doc.get("samplers", [{}])[tex["sampler"]] if "sampler" in tex else {}
        wrap = {33071: "clamp", 33648: "mirror", 10497: "repeat"}
        ws, wt = sampler.get("wrapS", 10497), sampler.get("wrapT", 10497)
        if ws != wt:
            self.note("different wrapS/wrapT: wrapS used")
        filt = "nearest" if sampler.get("magFilter") == 9728 else "bilinear"
        return {"type": "bitmap", "filename": lin, "raw": True,
                "filter_type": filt, "wrap_mode": wrap.get(ws, "repeat")}

    def bsdf(self, m):
        kind = classify(m)
        alpha = max(m["roughness"] ** 2, 1e-4)
        if "warn" in m:
            self.note("%s: %s" % (m["name"], m["warn"]))
        if kind == "lambert":
            b = {"type": "diffuse", "reflectance": self.base_color(m)}
        elif kind == "mirror":
            b = {"type": "conductor", "material": "none"}
        elif kind == "conductor":
            # Schlick Fresnel with F0 = baseColor, GGX alpha = r^2: Mitsuba's
            # principled BSDF with metallic = 1 is exactly that lobe (with the
            # separable Smith masking term).  A smooth coloured metal becomes a
            # (near-delta) alpha = 1e-3 lobe inside principled.
            b = {"type": "principled", "base_color": self.base_color(m),
                 "metallic": 1.0, "roughness": float(m["roughness"])}
        elif kind == "mixed_metal":
            self.note("%s: metallic %.3g between 0 and 1 -> principled (Disney "
                      "diffuse, not Lambert)" % (m["name"], m["metallic"]))
            b = {"type": "principled", "base_color": self.base_color(m),
                 "metallic": m["metallic"], "roughness": float(m["roughness"]),
                 "eta": m["ior"]}
        elif kind == "plastic":
            # lvcl's own layering (gltf_plastic.py), not Mitsuba's plastic.
            if any(c != 1.0 for c in m["specular_color"]):
                self.note("%s: specularColorFactor ignored, as lvcl does" % m["name"])
            f0 = ((m["ior"] - 1.0) / (m["ior"] + 1.0)) ** 2
            b = {"type": "gltf_plastic", "base": self.base_color(m), "specular": _rgb([m["specular"]] * 3),
                 "f0": f0, "alpha": m["roughness"] ** 2}
        elif kind == "solid_dielectric":
            if m["roughness"] > 0:
                b = {"type": "roughdielectric", "distribution": "ggx", "alpha": alpha,
                     "int_ior": m["ior"], "ext_ior": 1.0}
            else:
                b = {"type": "dielectric", "int_ior": m["ior"], "ext_ior": 1.0}
            if any(c != 1.0 for c in m["base"]) or m["base_tex"]:
                b["specular_transmittance"] = self.base_color(m)
            if m["transmission"] < 1.0:
                self.note("%s: transmissionFactor %.3g < 1 treated as 1"
                          % (m["name"], m["transmission"]))
            return b  # dielectrics are two-sided by nature
        else:  # thin_dielectric
            b = {"type": "thindielectric", "int_ior": m["ior"], "ext_ior": 1.0}
            if any(c != 1.0 for c in m["base"]) or m["base_tex"]:
                b["specular_transmittance"] = self.base_color(m)
            if m["roughness"] > 0:
                self.note("%s: rough thin dielectric rendered smooth" % m["name"])
            return b
        if m["double_sided"]:
            b = {"type": "twosided", "bsdf": b}
        return b

    def medium(self, m):
        """Interior medium for Beer-Lambert absorption, or None."""
        if classify(m) != "solid_dielectric" or not math.isfinite(m["att_dist"]) \
                or all(c >= 1.0 for c in m["att_color"]):
            return None
        sig = [-math.log(max(c, 1e-12)) / m["att_dist"] for c in m["att_color"]]
        # Mitsuba bounds an rgb volume value to [0, 1]: normalise and scale.
        # A channel that does not absorb (attenuation colour 1) keeps a
        # millionth of the largest: with sigma_t 0 in a channel, volpath
        # returns NaN for most pixels of the image (Mitsuba 3.9).
        top = max(sig)
        return {"type": "homogeneous", "albedo": 0.0,
                "sigma_t": _rgb([max(c / top, 1e-6) for c in sig]), "scale": top}


# --------------------------------------------------------------------- geometry

def write_ply(path, pos, faces, uv=None, normals=None):
    """Binary little-endian PLY: float x y z [nx ny nz] [u v], uchar/int face lists."""
    n, f = len(pos), len(faces)
    props = "property float x\nproperty float y\nproperty float z\n"
    if normals is not None:
        props += "property float nx\nproperty float ny\nproperty float nz\n"
    if uv is not None:
        props += "property float u\nproperty float v\n"
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\n%s"
              "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
              % (n, props, f))
    vert = pos.astype("<f4")
    if normals is not None:
        vert = np.concatenate([vert, normals.astype("<f4")], axis=1)
    if uv is not None:
        vert = np.concatenate([vert, uv.astype("<f4")], axis=1)
    frec = np.zeros(f, dtype=[("n", "u1"), ("i", "<i4", 3)])
    frec["n"] = 3
    frec["i"] = faces
    with open(path, "wb") as fh:
        fh.write(header.encode("ascii"))
        fh.write(np.ascontiguousarray(vert).tobytes())
        fh.write(frec.tobytes())


def primitive_triangles(g, prim):
    mode = prim.get("mode", 4)
    pos = g.accessor(prim["attributes"]["POSITION"]).astype(np.float64)
    if "indices" in prim:
        idx = g.accessor(prim["indices"]).reshape(-1).astype(np.int64)
    else:
        idx = np.arange(len(pos), dtype=np.int64)
    if mode == 4:
        tri = idx[: len(idx) // 3 * 3].reshape(-1, 3)
    elif mode == 5:  # strip
        t = [(idx[i], idx[i + 1], idx[i + 2]) if i % 2 == 0 else (idx[i + 1], idx[i], idx[i + 2])
             for i in range(len(idx) - 2)]
        tri = np.array(t, dtype=np.int64).reshape(-1, 3)
    elif mode == 6:  # fan
        tri = np.array([(idx[0], idx[i], idx[i + 1]) for i in range(1, len(idx) - 1)],
                       dtype=np.int64).reshape(-1, 3)
    else:
        return None, None, None
    uv = None
    if "TEXCOORD_0" in prim["attributes"]:
        uv = g.accessor(prim["attributes"]["TEXCOORD_0"]).astype(np.float64)
    # Drop degenerate (zero-area) triangles: they cannot be hit anyway.
    p0, p1, p2 = pos[tri[:, 0]], pos[tri[:, 1]], pos[tri[:, 2]]
    area = np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1)
    tri = tri[area > 0]
    return pos, tri, uv


def to_mitsuba_uv(uv):
    # glTF uv (0,0) is the first (top-left) texel of the image, v growing
    # downwards.  Mitsuba's PLY loader keeps (u, v) as stored and its bitmap
    # texture also maps v = 0 to the first (top) row, so no flip is needed
    # (checked with a 2x2 test texture).
    return uv


# --------------------------------------------------------------------- camera

def camera_to_world(world):
    """glTF camera: looks down local -Z, +Y up, +X right.  Mitsuba's
    perspective sensor looks down local +Z, +Y up, and its local +X points to
    the LEFT of the image (look_at builds left = up x dir).  So Mitsuba's
    frame is the glTF frame rotated 180 degrees about Y."""
    flip = np.diag([-1.0, 1.0, -1.0, 1.0])
    m = world @ flip
    # Remove scale from the rotation part (cameras ignore node scale).
    r = m[:3, :3]
    for k in range(3):
        nrm = np.linalg.norm(r[:, k])
        if nrm > 0:
            r[:, k] /= nrm
    m[:3, :3] = r
    return m


# --------------------------------------------------------------------- main entry

def convert(path, width=None, height=None, spp=64, workdir=None, seed=0,
            max_depth=64, rr_depth=5, camera_index=None):
    """Return (scene_dict, info).  Writes PLY/texture files into workdir."""
    import mitsuba as mi
    import gltf_plastic
    gltf_plastic.register()
    g = Gltf(path)
    doc = g.doc
    if workdir is None:
        workdir = tempfile.mkdtemp(prefix="gltf2mi_")
    os.makedirs(workdir, exist_ok=True)
    conv = Converter(g, workdir)
    scene = {"type": "scene"}
    info = {"shapes": 0, "triangles": 0, "emitters": 0, "materials": {}, "notes": conv.notes}

    nodes = list(walk_nodes(doc))
    mesh_users = {}
    for ni, w in nodes:
        if "mesh" in doc["nodes"][ni]:
            mesh_users.setdefault(doc["nodes"][ni]["mesh"], []).append((ni, w))

    bsdf_ids = {}

    def bsdf_ref(mat_index):
        key = "mat%s" % ("default" if mat_index is None else mat_index)
        if key not in bsdf_ids:
            m = material_info(doc, mat_index)
            scene[key] = conv.bsdf(m)
            bsdf_ids[key] = m
            info["materials"][m["name"]] = classify(m)
        return {"type": "ref", "id": key}

    any_medium = False
    shape_count = 0
    for mesh_i, users in sorted(mesh_users.items()):
        mesh = doc["meshes"][mesh_i]
        prims = []
        emissive = False
        for pi, prim in enumerate(mesh.get("primitives", [])):
            pos, tri, uv = primitive_triangles(g, prim)
            nrm = (g.accessor(prim["attributes"]["NORMAL"]).astype(np.float64)
                   if pos is not None and "NORMAL" in prim["attributes"] else None)
            if pos is None:
                conv.note("mesh %d primitive %d: non-triangle mode skipped" % (mesh_i, pi))
                continue
            if len(tri) == 0:
                continue
            m = material_info(doc, prim.get("material"))
            if any(c > 0 for c in m["emission"]):
                emissive = True
            if uv is not None and not m["base_tex"]:
                uv = None
            prims.append((pi, prim, pos, tri, uv, nrm, m))
        instanced = len(users) > 1 and not emissive
        if instanced:
            group = {"type": "shapegroup"}
            for pi, prim, pos, tri, uv, nrm, m in prims:
                fn = os.path.join(workdir, "m%d_p%d.ply" % (mesh_i, pi))
                write_ply(fn, pos, tri, None if uv is None else to_mitsuba_uv(uv), nrm)
                shp = {"type": "ply", "filename": fn, "face_normals": nrm is None,
                       "bsdf": bsdf_ref(prim.get("material"))}
                med = conv.medium(m)
                if med is not None:
                    shp["interior"] = med
                    any_medium = True
                group["p%d" % pi] = shp
            scene["group%d" % mesh_i] = group
            for ni, w in users:
                scene["inst%d" % ni] = {"type": "instance",
                                        "shapegroup": {"type": "ref", "id": "group%d" % mesh_i},
                                        "to_world": mi.ScalarTransform4f(w.tolist())}
                info["triangles"] += sum(len(p[3]) for p in prims)
            info["shapes"] += len(users)
            continue
        for ni, w in users:
            flip_winding = np.linalg.det(w[:3, :3]) < 0
            for pi, prim, pos, tri, uv, nrm, m in prims:
                wp = pos @ w[:3, :3].T + w[:3, 3]
                t = tri[:, ::-1] if flip_winding else tri
                wn = None
                if nrm is not None:  # normals by the inverse transpose
                    wn = nrm @ np.linalg.inv(w[:3, :3])
                    wn /= np.maximum(np.linalg.norm(wn, axis=1, keepdims=True), 1e-30)
                fn = os.path.join(workdir, "n%d_m%d_p%d.ply" % (ni, mesh_i, pi))
                write_ply(fn, wp, t, None if uv is None else to_mitsuba_uv(uv), wn)
                shp = {"type": "ply", "filename": fn, "face_normals": nrm is None,
                       "bsdf": bsdf_ref(prim.get("material"))}
                if any(c > 0 for c in m["emission"]):
                    # Mitsuba's area emitter emits on the side of the triangle
                    # normal cross(p1-p0, p2-p0), i.e. the CCW (glTF front) face.
                    shp["emitter"] = {"type": "area", "radiance": _rgb(m["emission"])}
                    info["emitters"] += 1
                med = conv.medium(m)
                if med is not None:
                    shp["interior"] = med
                    any_medium = True
                scene["shape%d" % shape_count] = shp
                shape_count += 1
                info["shapes"] += 1
                info["triangles"] += len(t)

    # Punctual lights.
    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    for ni, w in nodes:
        ext = doc["nodes"][ni].get("extensions", {}).get("KHR_lights_punctual")
        if ext is None:
            continue
        L = lights[ext["light"]]
        col = [float(c) * float(L.get("intensity", 1.0)) for c in L.get("color", [1, 1, 1])]
        pos = w[:3, 3]
        d = -w[:3, 2]
        d = d / (np.linalg.norm(d) or 1.0)
        if "range" in L:
            conv.note("light range ignored")
        if L["type"] == "point":
            scene["light%d" % ni] = {"type": "point", "position": pos.tolist(),
                                     "intensity": _rgb(col)}
        elif L["type"] == "spot":
            sp = L.get("spot", {})
            outer = float(sp.get("outerConeAngle", math.pi / 4))
            inner = float(sp.get("innerConeAngle", 0.0))
            up = [0.0, 1.0, 0.0] if abs(d[1]) < 0.99 else [1.0, 0.0, 0.0]
            scene["light%d" % ni] = {
                "type": "spot", "intensity": _rgb(col),
                "cutoff_angle": math.degrees(outer),
                "beam_width": math.degrees(min(inner, outer)),
                "to_world": mi.ScalarTransform4f().look_at(
                    origin=pos.tolist(), target=(pos + d).tolist(), up=up)}
            conv.note("spot falloff: Mitsuba interpolates linearly in angle between "
                      "beam_width and cutoff_angle; glTF suggests a smooth ramp in cos")
        elif L["type"] == "directional":
            scene["light%d" % ni] = {"type": "directional", "direction": d.tolist(),
                                     "irradiance": _rgb(col)}
        info["emitters"] += 1

    # Camera.
    cams = [(ni, w) for ni, w in nodes if "camera" in doc["nodes"][ni]]
    if not cams:
        raise GltfError("scene has no camera")
    ni, w = cams[camera_index or 0]
    cam = doc["cameras"][doc["nodes"][ni]["camera"]]
    if cam.get("type") != "perspective":
        raise GltfError("only perspective cameras are supported")
    p = cam["perspective"]
    aspect = float(p.get("aspectRatio", 1.0))
    if width is None and height is None:
        height = 256
    if width is None:
        width = max(1, int(round(height * aspect)))
    if height is None:
        height = max(1, int(round(width / aspect)))
    if abs(width / height - aspect) > 1e-3 * aspect:
        conv.note("image aspect %.4f differs from the camera's aspectRatio %.4f: "
                  "yfov kept" % (width / height, aspect))
    scene["sensor"] = {
        "type": "perspective",
        "fov": math.degrees(float(p["yfov"])), "fov_axis": "y",
        "near_clip": float(p.get("znear", 0.01)),
        "far_clip": float(p.get("zfar", 1e7)),
        "to_world": mi.ScalarTransform4f(camera_to_world(w).tolist()),
        "sampler": {"type": "independent", "sample_count": int(spp), "seed": int(seed)},
        "film": {"type": "hdrfilm", "width": int(width), "height": int(height),
                 "rfilter": {"type": "box"}, "pixel_format": "rgb",
                 "component_format": "float32"},
    }
    scene["integrator"] = {"type": "volpath" if any_medium else "path",
                           "max_depth": int(max_depth), "rr_depth": int(rr_depth)}
    if info["emitters"] == 0:
        conv.note("scene has no emitter: the image will be black")
    info["integrator"] = scene["integrator"]["type"]
    info["width"], info["height"] = width, height
    return scene, info


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--variant", default="scalar_rgb")
    a = ap.parse_args()
    import mitsuba as mi
    mi.set_variant(a.variant)
    try:
        d, info = convert(a.scene, a.width, a.height)
    except (GltfError, KeyError, ValueError, OSError) as e:
        print("gltf_to_mitsuba: %s: %s" % (a.scene, e), file=sys.stderr)
        return 1
    mi.load_dict(d)
    print(json.dumps(info, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
