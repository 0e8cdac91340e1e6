#!/usr/bin/env python3
"""Write the kitchen of the light-volume paper's Figure 4, procedurally.

Python 3 standard library only; deterministic output.  Usage:

    python3 scenes/make_kitchen.py smooth OUT.gltf     (few thousand triangles per tile)
    python3 scenes/make_kitchen.py rippled OUT.glb     (about 500,000 per tile)

A room 4 m (x) by 2.6 m (y) by 3.5 m (z) lit by a 0.8 m square ceiling
light (radiance 8).  The back wall (z = -1.75) and the left wall
(x = -2) are clad floor to ceiling in glossy tiles, as is the top of a
counter along the back wall; one tile mesh is stored once and placed by
one glTF node per tile (350 tiles).  A refrigerator stands 3 cm from the
left wall (the crack the paper mentions), and a glass table (a solid slab
on four legs) shelters a shoe.  The camera looks into the room from the
front right corner, 4:3.

The tile is 24 cm square on a 25 cm pitch (the wall shows in the 1 cm
grout lines), 6 mm proud of the wall at its centre, its rim rounded over
the outer 2 cm.  The smooth variant tessellates it into 32 x 32 quads
(2,048 triangles); the rippled variant into 500 x 500 quads (500,000
triangles) and adds ripples 0.8 mm deep across its face, so that the
rippled kitchen holds 175 million triangles as placed.  Both carry
smooth shading normals.
"""

import math
import os
import sys
from array import array

sys.dont_write_bytecode = True  # leave no __pycache__ in scenes/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_scenes import (Mesh, box, emission, flat_arrays, glass, gltf_document,  # noqa: E402
                         lambert, look_at, shoe_mesh, table, write_glb_file,
                         write_gltf_file)

X, Y, Z = 2.0, 2.6, 1.75          # the room: -X..X, 0..Y, -Z..Z
TILE, PITCH = 0.24, 0.25          # tile side and spacing, metres
TILE_HEIGHT, RIM = 0.006, 0.02    # how far the tile stands out; width of its rounded rim
RIPPLE_DEPTH, RIPPLE_WAVES = 0.0008, 6
COUNTER = (-1.2, 1.2, 0.6, 0.88)  # x0, x1, depth from the back wall, height


def glossy(name, rgb, roughness):
    """A glTF dielectric (a plastic: diffuse base under a GGX coat)."""
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": [float(c) for c in rgb] + [1.0],
                                     "metallicFactor": 0.0,
                                     "roughnessFactor": float(roughness)},
            "doubleSided": True}


def tile_height(x, y, rippled):
    """Height of the tile surface above its base at (x, y), |x|, |y| <= TILE/2."""
    h = TILE / 2.0

    def rim(d):  # 0 at the edge, 1 from RIM inwards, smooth in between
        t = min(max((h - abs(d)) / RIM, 0.0), 1.0)
        return math.sin(0.5 * math.pi * t)

    z = TILE_HEIGHT * rim(x) * rim(y)
    if rippled:
        k = 2.0 * math.pi * RIPPLE_WAVES / TILE
        z += RIPPLE_DEPTH * 0.5 * (math.sin(k * x) * math.cos(0.8 * k * y) + 1.0) * rim(x) * rim(y)
    return z


def tile_mesh(material, quads, rippled):
    """The tile as a height field over quads x quads quads, facing +z, with
    normals from central differences of the height."""
    n = quads + 1
    step = TILE / quads
    pos, nrm, idx = array("f"), array("f"), array("I")
    e = step * 0.5
    for j in range(n):
        y = -TILE / 2.0 + j * step
        for i in range(n):
            x = -TILE / 2.0 + i * step
            pos.extend((x, y, tile_height(x, y, rippled)))
            dx = (tile_height(x + e, y, rippled) - tile_height(x - e, y, rippled)) / (2.0 * e)
            dy = (tile_height(x, y + e, rippled) - tile_height(x, y - e, rippled)) / (2.0 * e)
            ln = math.sqrt(dx * dx + dy * dy + 1.0)
            nrm.extend((-dx / ln, -dy / ln, 1.0 / ln))
    for j in range(quads):
        for i in range(quads):
            a = j * n + i
            idx.extend((a, a + 1, a + n + 1, a, a + n + 1, a + n))
    mesh = flat_arrays(Mesh("tile", material))
    mesh.positions, mesh.normals, mesh.indices = pos, nrm, idx
    return mesh


def quaternion(axis, angle):
    s = math.sin(angle / 2.0)
    return [round(axis[0] * s, 9), round(axis[1] * s, 9), round(axis[2] * s, 9), round(math.cos(angle / 2.0), 9)]


def tile_placements():
    """One node per tile: the back wall above the counter and beside it, the
    left wall, the counter top. The tile faces its local +z."""
    out = []
    lift = 0.001  # tiles stand 1 mm off their surface
    back = quaternion((0, 0, 1), 0.0)
    left = quaternion((0, 1, 0), math.pi / 2.0)       # local +z -> world +x
    top = quaternion((1, 0, 0), -math.pi / 2.0)       # local +z -> world +y
    cols, rows = int(2 * X / PITCH), int(Y / PITCH)
    x0, x1, depth, height = COUNTER
    for r in range(rows):
        for c in range(cols):
            x, y = -X + (c + 0.5) * PITCH, (r + 0.5) * PITCH
            if x0 < x < x1 and y < height:
                continue  # behind the counter
            out.append({"translation": [x, y, -Z + lift], "rotation": back})
    for r in range(rows):
        for c in range(int(2 * Z / PITCH)):
            z, y = -Z + (c + 0.5) * PITCH, (r + 0.5) * PITCH
            out.append({"translation": [-X + lift, y, z], "rotation": left})
    for c in range(int((x1 - x0) / PITCH)):
        for d in range(int(depth / PITCH)):
            x, z = x0 + (c + 0.5) * PITCH, -Z + (d + 0.5) * PITCH
            out.append({"translation": [x, height + lift, z], "rotation": top})
    return [{k: ([round(v, 6) for v in p[k]] if k == "translation" else p[k]) for k in p} for p in out]


def kitchen(variant):
    WALL, FLOOR, CEILING, TILES, WOOD, FRIDGE, LEG, SHOE, GLASS, LIGHT = range(10)
    factor, strength = emission((8.0, 8.0, 8.0))
    materials = [
        lambert("walls", (0.75, 0.73, 0.7)),
        lambert("floor", (0.5, 0.42, 0.32)),
        lambert("ceiling", (0.8, 0.8, 0.8)),
        glossy("tiles", (0.55, 0.65, 0.75), 0.2),
        lambert("counter", (0.45, 0.3, 0.18)),
        glossy("fridge", (0.85, 0.85, 0.85), 0.15),
        lambert("legs", (0.2, 0.2, 0.2)),
        lambert("shoe", (0.65, 0.12, 0.06)),
        glass("glass", ior=1.5, thickness=0.03),
        lambert("light", (0.0, 0.0, 0.0), emissive=factor, strength=strength),
    ]
    up, down = (0.0, 1.0, 0.0), (0.0, -1.0, 0.0)

    walls = Mesh("walls", WALL)
    walls.quad([(-X, 0, -Z), (X, 0, -Z), (X, Y, -Z), (-X, Y, -Z)], (0, 0, 1))
    walls.quad([(-X, 0, -Z), (-X, 0, Z), (-X, Y, Z), (-X, Y, -Z)], (1, 0, 0))
    walls.quad([(X, 0, -Z), (X, 0, Z), (X, Y, Z), (X, Y, -Z)], (-1, 0, 0))
    walls.quad([(-X, 0, Z), (X, 0, Z), (X, Y, Z), (-X, Y, Z)], (0, 0, -1))
    floor = Mesh("floor", FLOOR)
    floor.quad([(-X, 0, -Z), (X, 0, -Z), (X, 0, Z), (-X, 0, Z)], up)
    ceiling = Mesh("ceiling", CEILING)
    ceiling.quad([(-X, Y, -Z), (X, Y, -Z), (X, Y, Z), (-X, Y, Z)], down)
    light = Mesh("light", LIGHT)
    ly, h = Y - 0.001, 0.4
    light.quad([(-h, ly, -h), (h, ly, -h), (h, ly, h), (-h, ly, h)], down)

    x0, x1, depth, height = COUNTER
    counter = Mesh("counter", WOOD)
    box(counter, (x0, 0.0, -Z + 0.007), (x1, height, -Z + depth))
    # The refrigerator: 0.75 m wide, 1.8 m tall, its side 3 cm from the
    # tiles of the left wall.
    fridge = Mesh("fridge", FRIDGE)
    fx = -X + 0.007 + 0.03
    box(fridge, (fx, 0.0, 0.1), (fx + 0.7, 1.8, 0.85))
    slab, legs = table(GLASS, LEG, (0.25, 0.05), 0.5, 0.35)
    shoe = shoe_mesh(SHOE, 0.25, 0.1)

    quads = 32 if variant == "smooth" else 500
    tile = tile_mesh(TILES, quads, variant == "rippled")
    tile.placements = tile_placements()

    eye, target = (1.9, 1.7, 1.7), (-0.6, 0.55, -0.6)
    camera = {"yfov": math.radians(55.0), "aspect": 4.0 / 3.0,
              "translation": list(eye), "rotation": look_at(eye, target)}
    meshes = [flat_arrays(m) for m in (walls, floor, ceiling, light, counter, fridge, slab, legs, shoe)] + [tile]
    note = ("the kitchen of the light-volume paper (Figure 4), %s tiles: %d triangles per tile, %d tiles"
            % (variant, 2 * quads * quads, len(tile.placements)))
    return gltf_document(meshes, materials, camera, "lvcl scenes/make_kitchen.py", note=note)


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("smooth", "rippled"):
        sys.exit("usage: make_kitchen.py smooth|rippled OUT.gltf|OUT.glb")
    variant, path = sys.argv[1], sys.argv[2]
    doc, blob = kitchen(variant)
    if path.endswith(".glb"):
        write_glb_file(path, doc, blob)
    else:
        write_gltf_file(path, doc, blob)


if __name__ == "__main__":
    main()
