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

Conventions (see DESIGN.md section 3): flat shading (no NORMAL attribute),
indexed triangles, front face = counter-clockwise winding, one buffer stored
as a base64 data URI.
"""

import base64
import json
import math
import os
import struct
import sys


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


def emission(radiance):
    """Radiance -> (emissiveFactor normalised to max 1, emissiveStrength)."""
    m = max(radiance)
    return [c / m for c in radiance], m


def write_gltf(path, meshes, materials, camera, generator_note):
    """meshes: list of Mesh; materials: list of material dicts (Mesh.material
    indexes it); camera: dict with yfov, aspect, translation, rotation (xyzw)."""
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
        pos = b"".join(struct.pack("<3f", *p) for p in m.positions)
        # min/max must bound the float32 values actually stored.
        f32 = [struct.unpack("<3f", struct.pack("<3f", *p)) for p in m.positions]
        lo = [min(p[k] for p in f32) for k in range(3)]
        hi = [max(p[k] for p in f32) for k in range(3)]
        vp = add_view(pos, 34962)
        accessors.append({"bufferView": vp, "componentType": 5126,
                          "count": len(m.positions), "type": "VEC3",
                          "min": lo, "max": hi})
        idx = b"".join(struct.pack("<I", i) for i in m.indices)
        vi = add_view(idx, 34963)
        accessors.append({"bufferView": vi, "componentType": 5125,
                          "count": len(m.indices), "type": "SCALAR",
                          "min": [min(m.indices)], "max": [max(m.indices)]})
        gl_meshes.append({"name": m.name, "primitives": [{
            "attributes": {"POSITION": len(accessors) - 2},
            "indices": len(accessors) - 1,
            "material": m.material, "mode": 4}]})
        nodes.append({"name": m.name, "mesh": len(gl_meshes) - 1})

    nodes.append({"name": "camera", "camera": 0,
                  "translation": list(camera["translation"]),
                  "rotation": list(camera["rotation"])})

    used = {"KHR_materials_specular"}
    for mat in materials:
        used.update(mat.get("extensions", {}).keys())

    doc = {
        "asset": {"version": "2.0",
                  "generator": "lvcl scenes/make_scenes.py",
                  "extras": {"note": generator_note}},
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
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(bytes(blob)).decode("ascii")}],
    }
    with open(path, "w", newline="\n") as f:
        json.dump(doc, f, indent=1, sort_keys=False)
        f.write("\n")
    ntri = sum(len(m.indices) // 3 for m in meshes)
    print("wrote %s (%d triangles)" % (path, ntri))


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


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out, exist_ok=True)
    cornell(os.path.join(out, "cornell.gltf"))
    furnace(os.path.join(out, "furnace.gltf"))


if __name__ == "__main__":
    main()
