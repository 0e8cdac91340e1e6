#!/usr/bin/env python3
"""Write the ray-throughput benchmark's large scene as a binary glTF (.glb).

Python 3 standard library only; deterministic output.  Usage:

    python3 bench/make_big_scene.py OUT.glb [--floor N]

A Cornell-like room, 2 m on a side and open at the front (-z): a white back
wall and ceiling, a red left and green right wall (as the camera sees them),
a floor rippled by a height field tessellated into N x N quads (default 670,
about 0.9M triangles) and 5 x 5 spheres of about 4k triangles each standing
on it: about 1.0M triangles in all.  A square area light just below the
ceiling emits downwards; the camera looks into the room along +z.

Materials are the project's Lambertian ones (scenes/make_scenes.py), flat
shading (no NORMAL attribute), counter-clockwise front faces.
"""

import math
import os
import sys
from array import array

sys.dont_write_bytecode = True  # leave no __pycache__ in scenes/
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes"))
# The project's material conventions and its one glTF document / .glb writer.
from make_scenes import emission, gltf_document, lambert, write_glb_file  # noqa: E402

RIPPLE_AMPLITUDE = 0.02  # metres
RIPPLE_WAVES = 6         # across the floor, in x and in z
SPHERE_RADIUS = 0.14
SPHERE_RINGS, SPHERE_SEGMENTS = 32, 64


class Mesh:
    """An indexed triangle list in float32 / uint32 arrays."""

    def __init__(self, name, material):
        self.name, self.material = name, material
        self.positions = array("f")
        self.indices = array("I")

    def vertex(self, x, y, z):
        self.positions.extend((x, y, z))
        return len(self.positions) // 3 - 1

    def quad(self, a, b, c, d):
        """Corners in counter-clockwise order seen from the front."""
        i = [self.vertex(*p) for p in (a, b, c, d)]
        self.indices.extend((i[0], i[1], i[2], i[0], i[2], i[3]))


def floor_height(x, z):
    k = 2.0 * math.pi * RIPPLE_WAVES / 2.0  # RIPPLE_WAVES periods over 2 m
    return RIPPLE_AMPLITUDE * math.sin(k * x) * math.sin(k * z)


def rippled_floor(n, material):
    """n x n quads over x, z in [-1, 1], facing up."""
    m = Mesh("floor", material)
    for j in range(n + 1):
        z = -1.0 + 2.0 * j / n
        for i in range(n + 1):
            x = -1.0 + 2.0 * i / n
            m.vertex(x, floor_height(x, z), z)
    row = n + 1
    for j in range(n):
        for i in range(n):
            a = j * row + i
            # a (x, z), b (x + dx, z), c (x + dx, z + dz), d (x, z + dz): seen
            # from above (+y) with x right and z down, a-d-c-b is counter-clockwise.
            b, c, d = a + 1, a + row + 1, a + row
            m.indices.extend((a, d, c, a, c, b))
    return m


def add_sphere(m, cx, cy, cz, r):
    """A latitude-longitude sphere, facing out; single triangles at the poles
    so that no triangle is degenerate."""
    first = len(m.positions) // 3
    for i in range(1, SPHERE_RINGS):  # rings between the poles
        theta = math.pi * i / SPHERE_RINGS
        for j in range(SPHERE_SEGMENTS):
            phi = 2.0 * math.pi * j / SPHERE_SEGMENTS
            m.vertex(cx + r * math.sin(theta) * math.cos(phi), cy + r * math.cos(theta),
                     cz + r * math.sin(theta) * math.sin(phi))
    top = m.vertex(cx, cy + r, cz)
    bottom = m.vertex(cx, cy - r, cz)

    def ring(i, j):
        return first + (i - 1) * SPHERE_SEGMENTS + j % SPHERE_SEGMENTS

    for j in range(SPHERE_SEGMENTS):
        # phi grows from +x towards +z, which seen from outside is clockwise
        # about +y, so each triangle lists the larger phi first.
        m.indices.extend((top, ring(1, j + 1), ring(1, j)))
        for i in range(1, SPHERE_RINGS - 1):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j + 1), ring(i + 1, j)
            m.indices.extend((a, b, c, a, c, d))
        last = SPHERE_RINGS - 1
        m.indices.extend((bottom, ring(last, j), ring(last, j + 1)))


def room():
    WHITE, RED, GREEN, LIGHT, SPHERES = range(5)
    factor, strength = emission((17.0, 12.0, 4.0))
    materials = [
        lambert("white", (0.725, 0.71, 0.68)),
        lambert("red", (0.63, 0.065, 0.05)),
        lambert("green", (0.14, 0.45, 0.091)),
        lambert("light", (0.0, 0.0, 0.0), emissive=factor, strength=strength),
        lambert("spheres", (0.5, 0.55, 0.7)),
    ]
    white = Mesh("walls", WHITE)
    white.quad((-1, 2, -1), (1, 2, -1), (1, 2, 1), (-1, 2, 1))     # ceiling, facing down
    white.quad((-1, 0, 1), (-1, 2, 1), (1, 2, 1), (1, 0, 1))       # back wall, facing -z
    red = Mesh("red_wall", RED)                                     # x = +1: the camera's left
    red.quad((1, 0, -1), (1, 0, 1), (1, 2, 1), (1, 2, -1))
    green = Mesh("green_wall", GREEN)                               # x = -1: the camera's right
    green.quad((-1, 0, 1), (-1, 0, -1), (-1, 2, -1), (-1, 2, 1))
    light = Mesh("light", LIGHT)                                    # 1 mm below the ceiling
    light.quad((-0.25, 1.999, -0.25), (0.25, 1.999, -0.25), (0.25, 1.999, 0.25), (-0.25, 1.999, 0.25))
    return materials, [white, red, green, light], SPHERES


def check_facing(mesh, tri, facing):
    i = mesh.indices[3 * tri: 3 * tri + 3]
    p = [mesh.positions[3 * k: 3 * k + 3] for k in i]
    e1 = [p[1][k] - p[0][k] for k in range(3)]
    e2 = [p[2][k] - p[0][k] for k in range(3)]
    n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
    assert sum(n[k] * facing[k] for k in range(3)) > 0.0, mesh.name


def main():
    args = sys.argv[1:]
    if not args or args[0].startswith("-"):
        sys.exit(__doc__)
    n = int(args[args.index("--floor") + 1]) if "--floor" in args else 670
    materials, meshes, sphere_material = room()
    floor = rippled_floor(n, 0)
    spheres = Mesh("spheres", sphere_material)
    for a in range(5):
        for b in range(5):
            x, z = -0.7 + 0.35 * a, -0.7 + 0.35 * b
            add_sphere(spheres, x, SPHERE_RADIUS + RIPPLE_AMPLITUDE, z, SPHERE_RADIUS)
    meshes += [floor, spheres]
    for mesh, facing in ((meshes[0], (0, -1, 0)), (meshes[1], (-1, 0, 0)), (meshes[2], (1, 0, 0)),
                         (meshes[3], (0, -1, 0)), (floor, (0, 1, 0)), (spheres, (0, 1, 0))):
        check_facing(mesh, 0, facing)
    check_facing(meshes[0], 2, (0, 0, -1))
    # Looking along +z from in front of the open side, far enough back that
    # the front opening fills the view (the Cornell box's framing); the glTF
    # camera looks down its local -z, hence the half turn about y. It stands
    # a little off the room's symmetry planes: on them, a whole diagonal of
    # pixels would aim exactly at the edges where walls meet the ceiling,
    # where a hit on either side is right and tracers differ by chance.
    yfov = 2.0 * math.atan(12.5 / 35.0)
    camera = {"yfov": yfov, "aspect": 1.0, "translation": [0.0123, 1.0071, -1.0 - 1.0 / math.tan(0.5 * yfov)],
              "rotation": [0.0, 1.0, 0.0, 0.0]}
    os.makedirs(os.path.dirname(os.path.abspath(args[0])), exist_ok=True)
    # Scanning ~3M indices for their optional min/max would only slow this down.
    doc, blob = gltf_document(meshes, materials, camera, "lvcl bench/make_big_scene.py",
                              index_bounds=False)
    write_glb_file(args[0], doc, blob)


if __name__ == "__main__":
    main()
