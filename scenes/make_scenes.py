#!/usr/bin/env python3
"""Write lvcl's own test scenes as self-contained glTF 2.0 files.

Python 3 standard library only; the output is deterministic (byte-identical on
every run).  Usage:

    python3 scenes/make_scenes.py [OUTDIR]      (default: the directory of this script)

Scenes written:

cornell.gltf  The Cornell box built from the published measurements of the
              Cornell University Program of Computer Graphics (millimetres in
              the published table, metres here).  Lambertian materials
              (metallic 0, KHR_materials_specular.specularFactor 0, doubleSided),
              a ceiling area light 1 mm below the ceiling emitting downwards
              with radiance (17, 12, 4) W m^-2 sr^-1, and the published pinhole
              camera (35 mm focal length, 25 mm film: yfov = 2 atan(12.5/35)).
              The red wall is at x = 0.55 m, which the camera (looking down +Z
              world) sees on its LEFT.
furnace.gltf  A white furnace: a closed cube room of side 2 m centred on the
              origin with every face facing inward, Lambertian albedo 0.5 and
              emitting radiance 1 from its (inward) front face, with the camera
              at the centre.  Every pixel should converge to Le / (1 - a) = 2.
glass-table.gltf
              The paper's "shoe under a glass table" (section 5).  A closed
              room 4 m (x) by 2.6 m (y) by 3 m (z) with Lambertian doubleSided
              walls of different albedos, a 1 m x 1 m ceiling area light 1 mm
              below the ceiling emitting downwards with radiance 5, a table
              whose top is a solid smooth glass slab (KHR_materials_transmission
              1, KHR_materials_volume thickness 0.03, KHR_materials_ior 1.5,
              roughness 0; a closed box wound outward, so the outside is the
              front face) 1.2 m x 0.8 m x 3 cm at 0.72..0.75 m on four thin
              grey legs, and a low-poly red "shoe" on the floor under the
              slab (242 triangles in all), lit through the glass.  The camera
              looks at the table from the front right and above (eye 1.05 m
              high, yfov 50 degrees).

Conventions (see docs/design.md, "Scene conventions"): flat shading (no NORMAL attribute),
indexed triangles, front face = counter-clockwise winding, one buffer stored
as a base64 data URI.
"""

import base64
import json
import math
import os
import struct
import sys
from array import array
from types import SimpleNamespace


# ---------------------------------------------------------------- vectors

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def mm(p):
    """Published millimetres -> metres."""
    return tuple(c / 1000.0 for c in p)


# ---------------------------------------------------------------- geometry

class Mesh:
    """An indexed triangle list built from planar quads (split into 2 triangles)."""

    def __init__(self, name, material):
        self.name = name
        self.material = material
        self.positions = []
        self.indices = []

    def quad(self, corners, facing):
        """Add quad a,b,c,d (given in order around its boundary).  The
        winding is chosen so that the front face (CCW) normal points along
        `facing` (a direction vector)."""
        a, b, c, d = corners
        n = cross(sub(b, a), sub(c, a))
        if dot(n, facing) < 0.0:
            a, b, c, d = d, c, b, a
        base = len(self.positions)
        self.positions += [a, b, c, d]
        self.indices += [base, base + 1, base + 2, base, base + 2, base + 3]
        # Sanity: both triangles face the requested way.
        for t in range(2):
            i0, i1, i2 = self.indices[-6 + 3 * t: -3 + 3 * t or None]
            p0, p1, p2 = (self.positions[i] for i in (i0, i1, i2))
            assert dot(cross(sub(p1, p0), sub(p2, p0)), facing) > 0.0, self.name

    def tri(self, corners, facing):
        """Add triangle a,b,c, wound so that its front face points along
        `facing`."""
        a, b, c = corners
        if dot(cross(sub(b, a), sub(c, a)), facing) < 0.0:
            b, c = c, b
        base = len(self.positions)
        self.positions += [a, b, c]
        self.indices += [base, base + 1, base + 2]


def block(mesh, top, height):
    """A block standing on the floor: `top` lists its 4 top corners (metres)
    in boundary order at y = height.  Adds the top and the four sides, all
    facing outward (no bottom face: it lies on the floor)."""
    cx = sum(p[0] for p in top) / 4.0
    cz = sum(p[2] for p in top) / 4.0
    mesh.quad(top, (0.0, 1.0, 0.0))
    for i in range(4):
        p, q = top[i], top[(i + 1) % 4]
        pb, qb = (p[0], 0.0, p[2]), (q[0], 0.0, q[2])
        mx, mz = (p[0] + q[0]) / 2.0 - cx, (p[2] + q[2]) / 2.0 - cz
        mesh.quad([pb, qb, q, p], (mx, 0.0, mz))


def box(mesh, lo, hi, inward=False):
    """A closed axis-aligned box from corner `lo` to corner `hi`, all six
    faces facing outward (or inward, for a room)."""
    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for s, c in ((-1.0, lo[axis]), (1.0, hi[axis])):
            corners = []
            for a, b in ((lo[u], lo[v]), (hi[u], lo[v]), (hi[u], hi[v]),
                         (lo[u], hi[v])):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = c, a, b
                corners.append(tuple(p))
            facing = [0.0, 0.0, 0.0]
            facing[axis] = -s if inward else s
            mesh.quad(corners, tuple(facing))


def loft(mesh, rings):
    """A closed-top solid lofted through `rings`, each a list of points
    (same count, same order) at one height, bottom ring first.  Adds the
    sides between consecutive rings (facing away from the ring centres) and
    a fan over the top ring (facing up); no bottom face (it lies on the
    floor)."""
    n = len(rings[0])

    def centre(r):
        return tuple(sum(p[k] for p in r) / len(r) for k in range(3))

    for lo, hi in zip(rings, rings[1:]):
        c = centre(lo + hi)
        for i in range(n):
            j = (i + 1) % n
            m = tuple((lo[i][k] + lo[j][k] + hi[i][k] + hi[j][k]) / 4.0
                      for k in range(3))
            mesh.quad([lo[i], lo[j], hi[j], hi[i]], (m[0] - c[0], 0.0, m[2] - c[2]))
    top = rings[-1]
    c = centre(top)
    for i in range(n):
        mesh.tri([c, top[i], top[(i + 1) % n]], (0.0, 1.0, 0.0))


def look_at(eye, target, up=(0.0, 1.0, 0.0)):
    """Unit quaternion (x, y, z, w) turning a glTF camera (looking down its
    local -Z, +Y up) at `eye` towards `target`."""
    def norm(a):
        ln = math.sqrt(dot(a, a))
        return (a[0] / ln, a[1] / ln, a[2] / ln)
    back = norm(sub(eye, target))            # local +Z
    right = norm(cross(up, back))            # local +X
    upv = cross(back, right)                 # local +Y
    # Rotation matrix with columns right, upv, back -> quaternion.
    m00, m01, m02 = right[0], upv[0], back[0]
    m10, m11, m12 = right[1], upv[1], back[1]
    m20, m21, m22 = right[2], upv[2], back[2]
    tr = m00 + m11 + m22
    if tr > 0.0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = ((m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s)
    elif m00 > m11 and m00 > m22:
        s = 2.0 * math.sqrt(1.0 + m00 - m11 - m22)
        q = (0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s)
    elif m11 > m22:
        s = 2.0 * math.sqrt(1.0 + m11 - m00 - m22)
        q = ((m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m22 - m00 - m11)
        q = ((m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s)
    return [round(c, 9) for c in q]


# ---------------------------------------------------------------- glTF writer

def lambert(name, rgb, double_sided=True, emissive=None, strength=None):
    mat = {
        "name": name,
        "pbrMetallicRoughness": {
            "baseColorFactor": [float(c) for c in rgb] + [1.0],
            "metallicFactor": 0.0,
            "roughnessFactor": 1.0,
        },
        "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}},
        "doubleSided": bool(double_sided),
    }
    if emissive is not None:
        mat["emissiveFactor"] = [float(c) for c in emissive]
        if strength is not None and strength != 1.0:
            mat["extensions"]["KHR_materials_emissive_strength"] = {
                "emissiveStrength": float(strength)}
    return mat


def glass(name, ior=1.5, thickness=1.0):
    """Solid smooth dielectric (docs/design.md, "Scene conventions"): transmission 1,
    volume thickness > 0, roughness 0, the front face is the outside."""
    return {
        "name": name,
        "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
            "metallicFactor": 0.0,
            "roughnessFactor": 0.0,
        },
        "extensions": {
            "KHR_materials_transmission": {"transmissionFactor": 1.0},
            "KHR_materials_volume": {"thicknessFactor": float(thickness)},
            "KHR_materials_ior": {"ior": float(ior)},
        },
        "doubleSided": False,
    }


def emission(radiance):
    """Radiance -> (emissiveFactor normalised to max 1, emissiveStrength)."""
    m = max(radiance)
    return [c / m for c in radiance], m


def flat_arrays(m):
    """m (a Mesh) as gltf_document() takes it: name, material, positions as a
    flat float32 array, indices as a uint32 array (bench/make_big_scene.py
    builds that form directly, for speed)."""
    return SimpleNamespace(name=m.name, material=m.material,
                           positions=array("f", [c for p in m.positions for c in p]),
                           indices=array("I", m.indices))


def little_endian(a):
    """a's bytes as glTF stores them (little-endian, whatever this machine is)."""
    if sys.byteorder == "big":
        a = array(a.typecode, a)
        a.byteswap()
    return a.tobytes()


def gltf_document(meshes, materials, camera, generator, note=None, index_bounds=True):
    """The glTF document (a dict, without a buffer URI) and its one binary
    buffer.  meshes: objects with name, material (an index into materials),
    positions (flat float32 array) and indices (uint32 array), and
    optionally normals (flat float32 array, for smooth shading) and
    placements (a list of node properties such as translation, rotation,
    scale: one node each, so the mesh is stored once and instanced; by
    default one node in place); camera: dict
    with yfov, aspect, translation, rotation (xyzw) and optionally znear.
    index_bounds: also record the indices' min/max, which glTF leaves
    optional (the big benchmark scene has never had them)."""
    assert array("I").itemsize == 4
    blob = bytearray()
    accessors, views = [], []

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob),
                      "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(views) - 1

    gl_meshes, nodes = [], []
    for m in meshes:
        pos = m.positions
        # min/max must bound the float32 values actually stored, which the
        # float32 array already holds.
        lo = [min(pos[k::3]) for k in range(3)]
        hi = [max(pos[k::3]) for k in range(3)]
        vp = add_view(little_endian(pos), 34962)
        accessors.append({"bufferView": vp, "componentType": 5126,
                          "count": len(pos) // 3, "type": "VEC3",
                          "min": lo, "max": hi})
        vi = add_view(little_endian(m.indices), 34963)
        accessors.append({"bufferView": vi, "componentType": 5125,
                          "count": len(m.indices), "type": "SCALAR"})
        if index_bounds:
            accessors[-1].update({"min": [min(m.indices)], "max": [max(m.indices)]})
        attributes = {"POSITION": len(accessors) - 2}
        indices = len(accessors) - 1
        if getattr(m, "normals", None) is not None:
            vn = add_view(little_endian(m.normals), 34962)
            accessors.append({"bufferView": vn, "componentType": 5126,
                              "count": len(m.normals) // 3, "type": "VEC3"})
            attributes["NORMAL"] = len(accessors) - 1
        gl_meshes.append({"name": m.name, "primitives": [{
            "attributes": attributes,
            "indices": indices,
            "material": m.material, "mode": 4}]})
        for placement in getattr(m, "placements", None) or [{}]:
            nodes.append(dict({"name": m.name, "mesh": len(gl_meshes) - 1}, **placement))

    nodes.append({"name": "camera", "camera": 0,
                  "translation": list(camera["translation"]),
                  "rotation": list(camera["rotation"])})

    used = {"KHR_materials_specular"}
    for mat in materials:
        used.update(mat.get("extensions", {}).keys())

    asset = {"version": "2.0", "generator": generator}
    if note is not None:
        asset["extras"] = {"note": note}
    doc = {
        "asset": asset,
        "extensionsUsed": sorted(used),
        "scene": 0,
        "scenes": [{"name": "scene", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": gl_meshes,
        "materials": materials,
        "cameras": [{"name": "camera", "type": "perspective",
                     "perspective": {"yfov": camera["yfov"],
                                     "aspectRatio": camera["aspect"],
                                     "znear": camera.get("znear", 0.01)}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }
    return doc, blob


def report(path, doc):
    ntri = sum(a["count"] for a in doc["accessors"] if a["type"] == "SCALAR") // 3
    print("wrote %s (%d triangles)" % (path, ntri))


def write_gltf_file(path, doc, blob):
    """A self-contained .gltf: the buffer as a base64 data URI, readable JSON."""
    doc["buffers"][0]["uri"] = ("data:application/octet-stream;base64,"
                                + base64.b64encode(bytes(blob)).decode("ascii"))
    with open(path, "w", newline="\n") as f:
        json.dump(doc, f, indent=1, sort_keys=False)
        f.write("\n")
    report(path, doc)


def write_glb_file(path, doc, blob):
    """A binary .glb: compact JSON chunk then the buffer as the BIN chunk,
    each padded to 4 bytes as the container requires."""
    js = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    js += b" " * (-len(js) % 4)
    blob = bytes(blob) + b"\0" * (-len(blob) % 4)
    total = 12 + 8 + len(js) + 8 + len(blob)
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total))
        f.write(struct.pack("<I4s", len(js), b"JSON") + js)
        f.write(struct.pack("<I4s", len(blob), b"BIN\0") + blob)
    report(path, doc)


def write_gltf(path, meshes, materials, camera, generator_note):
    """meshes: list of Mesh; materials: list of material dicts (Mesh.material
    indexes it); camera: as gltf_document() takes it."""
    doc, blob = gltf_document([flat_arrays(m) for m in meshes], materials, camera,
                              "lvcl scenes/make_scenes.py", note=generator_note)
    write_gltf_file(path, doc, blob)


# ---------------------------------------------------------------- scenes

def cornell(path):
    WHITE, RED, GREEN, LIGHT = 0, 1, 2, 3
    le = (17.0, 12.0, 4.0)
    factor, strength = emission(le)
    materials = [
        lambert("white", (0.725, 0.71, 0.68)),
        lambert("red", (0.63, 0.065, 0.05)),
        lambert("green", (0.14, 0.45, 0.091)),
        lambert("light", (0.0, 0.0, 0.0), emissive=factor, strength=strength),
    ]
    up, down = (0.0, 1.0, 0.0), (0.0, -1.0, 0.0)

    walls = Mesh("white_walls", WHITE)
    # Floor, ceiling and back wall (published mm values), facing into the box.
    walls.quad([mm((552.8, 0, 0)), mm((0, 0, 0)), mm((0, 0, 559.2)),
                mm((549.6, 0, 559.2))], up)
    walls.quad([mm((556.0, 548.8, 0)), mm((556.0, 548.8, 559.2)),
                mm((0, 548.8, 559.2)), mm((0, 548.8, 0))], down)
    walls.quad([mm((549.6, 0, 559.2)), mm((0, 0, 559.2)),
                mm((0, 548.8, 559.2)), mm((556.0, 548.8, 559.2))],
               (0.0, 0.0, -1.0))

    red = Mesh("red_wall", RED)          # x ~ 0.55: the camera's left
    red.quad([mm((552.8, 0, 0)), mm((549.6, 0, 559.2)),
              mm((556.0, 548.8, 559.2)), mm((556.0, 548.8, 0))],
             (-1.0, 0.0, 0.0))

    green = Mesh("green_wall", GREEN)    # x = 0: the camera's right
    green.quad([mm((0, 0, 559.2)), mm((0, 0, 0)), mm((0, 548.8, 0)),
                mm((0, 548.8, 559.2))], (1.0, 0.0, 0.0))

    # Published light rectangle (343..213 x 227..332 mm), lowered 1 mm below
    # the ceiling so that it does not coincide with it; front face down.
    ly = 0.5478
    light = Mesh("light", LIGHT)
    light.quad([(0.343, ly, 0.227), (0.343, ly, 0.332), (0.213, ly, 0.332),
                (0.213, ly, 0.227)], down)

    short = Mesh("short_block", WHITE)
    block(short, [mm((130.0, 165.0, 65.0)), mm((82.0, 165.0, 225.0)),
                  mm((240.0, 165.0, 272.0)), mm((290.0, 165.0, 114.0))], 0.165)
    tall = Mesh("tall_block", WHITE)
    block(tall, [mm((423.0, 330.0, 247.0)), mm((265.0, 330.0, 296.0)),
                 mm((314.0, 330.0, 456.0)), mm((472.0, 330.0, 406.0))], 0.330)

    # Published camera: eye (278, 273, -800) mm looking down +Z world, up +Y.
    # The glTF camera looks down its local -Z, so rotate it by 180 degrees
    # about Y: quaternion (x, y, z, w) = (0, 1, 0, 0).
    camera = {"yfov": 2.0 * math.atan(12.5 / 35.0), "aspect": 1.0,
              "translation": [0.278, 0.273, -0.8],
              "rotation": [0.0, 1.0, 0.0, 0.0]}
    write_gltf(path, [walls, red, green, light, short, tall], materials,
               camera, "Cornell box from the published measurements; "
                       "light radiance (17,12,4)")


def furnace(path):
    h = 1.0
    materials = [lambert("furnace", (0.5, 0.5, 0.5), double_sided=False,
                         emissive=(1.0, 1.0, 1.0), strength=1.0)]
    room = Mesh("room", 0)
    for axis in range(3):
        for s in (-1.0, 1.0):
            # Face at coordinate s*h on `axis`, facing inward (-s).
            u, v = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for a, b in ((-h, -h), (h, -h), (h, h), (-h, h)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = s * h, a, b
                corners.append(tuple(p))
            facing = [0.0, 0.0, 0.0]
            facing[axis] = -s
            room.quad(corners, tuple(facing))
    camera = {"yfov": math.radians(90.0), "aspect": 1.0,
              "translation": [0.0, 0.0, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0]}
    write_gltf(path, [room], materials, camera,
               "white furnace: albedo 0.5, Le 1, expected radiance 2")


def table(slab_material, leg_material, centre, tx, tz, t0=0.72, t1=0.75):
    """A table centred at `centre` (x, z): a slab 2 tx by 2 tz between
    heights t0 and t1, on legs of 4 cm square section that stop 1 mm below
    the slab. Returns the slab and the legs."""
    cx, cz = centre
    slab = Mesh("glass_top", slab_material)
    box(slab, (cx - tx, t0, cz - tz), (cx + tx, t1, cz + tz))
    legs = Mesh("legs", leg_material)
    w, inset, lh = 0.04, 0.05, t0 - 0.001
    for sx in (-1.0, 1.0):
        for sz in (-1.0, 1.0):
            x0 = cx + sx * (tx - inset) - w / 2.0
            z0 = cz + sz * (tz - inset) - w / 2.0
            block(legs, [(x0, lh, z0), (x0 + w, lh, z0),
                         (x0 + w, lh, z0 + w), (x0, lh, z0 + w)], lh)
    return slab, legs


def shoe_mesh(material, x, z):
    """A 32 cm long shoe standing on the floor, toe towards +x, its sole
    centred near (x, z): a rounded footprint, wider at the toe, lofted up
    through rings that shrink towards the heel."""
    n, xh, length = 16, x - 0.14, 0.32
    foot = []
    for i in range(n):
        t = 2.0 * math.pi * i / n
        u = 0.5 - 0.5 * math.cos(t)                  # 0 at the heel, 1 at the toe
        half = 0.042 + 0.018 * u
        foot.append((xh + length * u, half * math.sin(t)))
    rings = []
    for y, sx, sw in ((0.0, 1.0, 1.0), (0.03, 1.0, 1.0), (0.035, 0.96, 0.92),
                      (0.08, 0.9, 0.88), (0.115, 0.6, 0.8), (0.16, 0.36, 0.72)):
        rings.append([(xh + 0.006 * (1.0 - sw) + (px - xh) * sx, y,
                       z + pz * sw) for px, pz in foot])
    shoe = Mesh("shoe", material)
    loft(shoe, rings)
    return shoe


def glass_table(path):
    FLOOR, CEIL, BACK, LEFT, SIDE, LEG, SHOE, GLASS, LIGHT = range(9)
    le = (5.0, 5.0, 5.0)
    factor, strength = emission(le)
    materials = [
        lambert("floor", (0.55, 0.45, 0.35)),
        lambert("ceiling", (0.8, 0.8, 0.8)),
        lambert("back_wall", (0.35, 0.45, 0.65)),
        lambert("left_wall", (0.45, 0.6, 0.35)),
        lambert("white_walls", (0.7, 0.7, 0.7)),
        lambert("legs", (0.2, 0.2, 0.2)),
        lambert("shoe", (0.65, 0.12, 0.06)),
        glass("glass", ior=1.5, thickness=0.03),
        lambert("light", (0.0, 0.0, 0.0), emissive=factor, strength=strength),
    ]
    X, Y, Z = 2.0, 2.6, 1.5          # room: -X..X, 0..Y, -Z..Z
    up, down = (0.0, 1.0, 0.0), (0.0, -1.0, 0.0)

    def wall(name, mat, corners, facing):
        m = Mesh(name, mat)
        m.quad(corners, facing)
        return m

    floor = wall("floor", FLOOR, [(-X, 0.0, -Z), (X, 0.0, -Z), (X, 0.0, Z),
                                  (-X, 0.0, Z)], up)
    ceiling = wall("ceiling", CEIL, [(-X, Y, -Z), (X, Y, -Z), (X, Y, Z),
                                     (-X, Y, Z)], down)
    back = wall("back_wall", BACK, [(-X, 0.0, -Z), (X, 0.0, -Z), (X, Y, -Z),
                                    (-X, Y, -Z)], (0.0, 0.0, 1.0))
    left = wall("left_wall", LEFT, [(-X, 0.0, -Z), (-X, 0.0, Z), (-X, Y, Z),
                                    (-X, Y, -Z)], (1.0, 0.0, 0.0))
    sides = Mesh("white_walls", SIDE)     # right wall and the wall behind the camera
    sides.quad([(X, 0.0, -Z), (X, 0.0, Z), (X, Y, Z), (X, Y, -Z)],
               (-1.0, 0.0, 0.0))
    sides.quad([(-X, 0.0, Z), (X, 0.0, Z), (X, Y, Z), (-X, Y, Z)],
               (0.0, 0.0, -1.0))

    # Ceiling light, 1 m x 1 m above the table, 1 mm below the ceiling.
    ly, h = Y - 0.001, 0.5
    light = wall("light", LIGHT, [(-h, ly, -h), (h, ly, -h), (h, ly, h),
                                  (-h, ly, h)], down)

    slab, legs = table(GLASS, LEG, (0.0, 0.0), 0.6, 0.4)
    shoe = shoe_mesh(SHOE, 0.0, 0.05)

    eye, target = (1.1, 1.05, 1.45), (0.0, 0.33, -0.05)
    camera = {"yfov": math.radians(50.0), "aspect": 1.0,
              "translation": list(eye), "rotation": look_at(eye, target)}
    write_gltf(path, [floor, ceiling, back, left, sides, light, slab, legs,
                      shoe], materials, camera,
               "shoe under a glass table (paper section 5); light radiance 5, "
               "glass ior 1.5")


def thin_wall(path):
    """Two sealed rooms side by side, split by a 2 cm wall that no grid
    aligns with; only the left room has a lamp, so every bit of light seen
    in the right room is a leak (a light-volume test, issue 4)."""
    WHITE, LIGHT = range(2)
    factor, strength = emission((10.0, 10.0, 10.0))
    materials = [lambert("white", (0.7, 0.7, 0.7)),
                 lambert("light", (0.0, 0.0, 0.0), emissive=factor, strength=strength)]
    X, Y, Z, wall_x = 2.0, 2.5, 1.0, 0.37
    room = Mesh("room", WHITE)
    box(room, (-X, 0.0, -Z), (X, Y, Z), inward=True)
    box(room, (wall_x - 0.01, 0.0, -Z), (wall_x + 0.01, Y, Z))
    lamp = Mesh("lamp", LIGHT)
    lamp.quad([(-1.4, Y - 0.001, -0.3), (-0.8, Y - 0.001, -0.3), (-0.8, Y - 0.001, 0.3),
               (-1.4, Y - 0.001, 0.3)], (0.0, -1.0, 0.0))
    eye, target = (1.9, 1.2, 0.0), (wall_x, 1.1, 0.0)
    camera = {"yfov": math.radians(70.0), "aspect": 1.0,
              "translation": list(eye), "rotation": look_at(eye, target)}
    write_gltf(path, [room, lamp], materials, camera,
               "two sealed rooms, lamp in the left one; the camera looks at the dividing wall "
               "from the dark right room, where the true radiance is 0")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out, exist_ok=True)
    cornell(os.path.join(out, "cornell.gltf"))
    furnace(os.path.join(out, "furnace.gltf"))
    glass_table(os.path.join(out, "glass-table.gltf"))
    thin_wall(os.path.join(out, "thin-wall.gltf"))


if __name__ == "__main__":
    main()
