#!/usr/bin/env python3
"""Two closed rooms sharing a wall, each with its own ceiling lamp (issue 12):
the camera stands in the dim room and looks at the shared wall. Rendering
the dim room with the bright lamp on and off tells whether the light volume
leaks the bright room's light through the cells the wall cuts (the true
ratio, and the path tracer's, is 1).

    python3 scenes/make_two_rooms.py OUT.gltf --thickness 0.02 --ratio 25 [--bright-off | --dim-off]
        [--shell 0.1] [--panel 0.04] [--door 0.1] [--yaw 12 --pitch 7] [--scale 100]
        [--wall-material lambert|glossy|mirror] [--bright-light area|point|spot]
        [--bend 0.4 [--bend-rows 5]] [--split -0.3] [--look-at X,Y,Z --fov 1e-5] [--gable 0.4 [--ridge 0.35]]

--thickness 0 makes the wall one double-sided polygon; --shell S builds the
outer walls, floor and ceiling as slabs S thick; --panel D stands a
cupboard D deep against the wall in the camera's room; --door W leaves a
doorway W wide and 2 m tall in the wall, so that with --dim-off the
camera's room is lit only through it (issue 14's door ajar, where guided
paths help most); --yaw and --pitch turn the
whole scene (degrees, about y and then x), so that no wall faces a grid
axis; --scale multiplies every length (radiance, and so the image, stay
the same); --wall-material gives the shared wall(s) a finish of their own;
--bright-light replaces the bright lamp by a point or spot light of its
power; --bend bows the shared wall (--thickness 0) into the camera's room,
so that no cell's plane fits it; --look-at and --fov aim the camera (a
field of view of 1e-5 degrees puts every pixel within a few hundred
nanometres of the point: onto the line where the wall meets the floor,
say); --split adds a wall across the camera's side, ending against the
shared one (a T), with a bright room beyond it; --gable E puts the rooms
under a gable roof, eaves E high and the ridge at the ceiling's height
over z = --ridge, so that the shared wall is a pentagon (one polygon or a
slab) and meets two sloping roof planes. Without --gable the geometry is
the same as tests/volume/test_two_rooms.c builds in memory."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_scenes import (Mesh, box, emission, flat_arrays, gltf_document, lambert, look_at,  # noqa: E402
                         write_gltf_file)

X, Y, Z, WALL_X = 2.0, 2.5, 1.0, 0.37   # rooms x in [-X, X], split at WALL_X
DIM_LE = 4.0                            # the dim room's lamp radiance


def turn(p, yaw, pitch):
    """p turned by yaw about y, then by pitch about x (radians)."""
    x = math.cos(yaw) * p[0] + math.sin(yaw) * p[2]
    z = -math.sin(yaw) * p[0] + math.cos(yaw) * p[2]
    return (x, math.cos(pitch) * p[1] - math.sin(pitch) * z, math.sin(pitch) * p[1] + math.cos(pitch) * z)


def quat_mul(a, b):
    """The rotation b then a, as glTF quaternions (x, y, z, w)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]


DOOR_Z, DOOR_TOP = -0.6, 2.0             # a doorway's near edge and its height


def bowed_wall(mesh, bend, rows, columns=16):
    """The shared wall of one polygon bowed `bend` into the camera's room
    at its middle (x = WALL_X + bend cos(pi z / 2Z)), `rows` rows of
    `columns` quads facing +x (tests/volume/test_two_rooms.c builds the same)."""
    def x(z):
        return WALL_X + bend * math.cos(math.pi * z / (2 * Z))
    for i in range(columns):
        z0, z1 = -Z + 2 * Z * i / columns, -Z + 2 * Z * (i + 1) / columns
        for j in range(rows):
            y0, y1 = Y * j / rows, Y * (j + 1) / rows
            mesh.quad([(x(z0), y0, z0), (x(z1), y0, z1), (x(z1), y1, z1), (x(z0), y1, z0)], (1.0, 0.0, 0.0))


def gable_section(x, eave, ridge):
    """The rooms' cross-section under a gable roof at x: a pentagon, its
    corners in order round its boundary."""
    return [(x, 0.0, -Z), (x, 0.0, Z), (x, eave, Z), (x, Y, ridge), (x, eave, -Z)]


def roof_height(z, eave, ridge):
    """The gable roof's height over z: eave at z = -Z and Z, Y over z = ridge."""
    return eave + (Y - eave) * ((z + Z) / (ridge + Z) if z <= ridge else (Z - z) / (Z - ridge))


def pentagon(mesh, p, facing):
    """Adds pentagon p (corners in order round it) facing along `facing`."""
    mesh.quad(p[:4], facing)
    mesh.tri([p[0], p[3], p[4]], facing)


def gable_rooms(room, shared, eave, ridge, thickness):
    """The rooms of one polygon each side under a gable roof (floor, the
    walls at z = -Z and Z up to the eaves, two roof planes to the ridge,
    pentagon end walls), all facing in, and the shared wall: a pentagon
    facing +x, or a slab `thickness` thick (a pentagonal prism)."""
    room.quad([(-X, 0, -Z), (X, 0, -Z), (X, 0, Z), (-X, 0, Z)], (0.0, 1.0, 0.0))
    for z in (-Z, Z):
        room.quad([(-X, 0, z), (X, 0, z), (X, eave, z), (-X, eave, z)], (0.0, 0.0, -z))
        # The roof plane from this eave to the ridge, facing down and in.
        room.quad([(-X, eave, z), (X, eave, z), (X, Y, ridge), (-X, Y, ridge)], (0.0, -abs(ridge - z), (Y - eave) * -z))
    for x in (-X, X):
        pentagon(room, gable_section(x, eave, ridge), (-x, 0.0, 0.0))
    if thickness <= 0:
        pentagon(shared, gable_section(WALL_X, eave, ridge), (1.0, 0.0, 0.0))
        return
    a, b = gable_section(WALL_X - thickness / 2, eave, ridge), gable_section(WALL_X + thickness / 2, eave, ridge)
    pentagon(shared, a, (-1.0, 0.0, 0.0))
    pentagon(shared, b, (1.0, 0.0, 0.0))
    middle = (0.0, (eave + Y) / 3, ridge / 3)
    for i in range(5):
        j = (i + 1) % 5
        edge = [(a[i][k] + a[j][k]) / 2 for k in range(3)]
        shared.quad([a[i], a[j], b[j], b[i]], (0.0, edge[1] - middle[1], edge[2] - middle[2]))


def two_rooms(path, thickness, ratio, bright_on, colours=False, shell=0.0, panel=0.0, yaw=0.0, pitch=0.0,
              door=0.0, dim_on=True, corridor=0.0, back_to_back=False, scale=1.0, wall_material="lambert",
              bright_light="area", bend=0.0, bend_rows=1, look_at_point=None, fov_deg=70.0, split=None, sun=False,
              gable=None, ridge=0.0):
    """colours: the bright lamp red and the dim one blue (grey walls keep
    the channels apart), so that any red in the dim room is a leak.
    scale: every length times this (radiance is the same, so the image
    is too); wall_material: the shared wall(s) lambert, glossy (plastic,
    roughness 0.3) or mirror (metal, roughness 0); bright_light: area (the
    ceiling lamp), point or spot (a KHR_lights_punctual light of the same
    power at the lamp's centre; spot: 60 degrees, pointing down); bend: the
    shared wall, of one polygon, bowed that far into the camera's room
    (bowed_wall; thickness 0, no doorway or corridor); look_at_point: where
    the camera looks (in the scene's own frame, before the turn and scale;
    None: the middle of the wall), fov_deg its vertical field of view;
    split: a wall like the shared one across the camera's side at z =
    split (-0.45 to -0.1), from the shared wall to the outer wall, and a
    third lamp, as bright as the bright one, beyond it: the two walls meet
    in a T, and a hit on the end of the second lies on the first's plane
    (no cupboard, corridor or bow); gable: the eaves' height of a gable
    roof whose ridge runs over z = ridge (gable_rooms; one-polygon rooms
    without slabs, doorway, corridor, cupboard, bow or split); the lamps
    then hang 20 cm under the roof, 30 cm deep under the ridge (half the
    area), and the camera 25 cm below them."""
    WHITE, DIM, BRIGHT, WALL = range(4)
    dim_le = DIM_LE if dim_on else 0.0
    bright_le = DIM_LE * ratio if bright_on else 0.0
    materials = [lambert("white", (0.7, 0.7, 0.7))]
    if dim_on:
        f, s = emission((0.0, 0.0, dim_le) if colours else (dim_le,) * 3)
        materials.append(lambert("dim lamp", (0.0, 0.0, 0.0), emissive=f, strength=s))
    else:
        materials.append(lambert("dim lamp (off)", (0.0, 0.0, 0.0)))
    if bright_on:
        f, s = emission((bright_le, 0.0, 0.0) if colours else (bright_le,) * 3)
        materials.append(lambert("bright lamp", (0.0, 0.0, 0.0), emissive=f, strength=s))
    else:
        materials.append(lambert("bright lamp (off)", (0.0, 0.0, 0.0)))
    wall = lambert("shared wall (%s)" % wall_material, (0.7, 0.7, 0.7))
    if wall_material == "glossy":
        wall["pbrMetallicRoughness"]["roughnessFactor"] = 0.3
        del wall["extensions"]
    elif wall_material == "mirror":
        wall["pbrMetallicRoughness"].update({"metallicFactor": 1.0, "roughnessFactor": 0.0})
        del wall["extensions"]
    materials.append(wall)
    room = Mesh("rooms", WHITE)
    shared = Mesh("shared wall", WALL)
    lo, hi = (-X, 0.0, -Z), (X, Y, Z)
    lamp_y, lamp_z, eye_y = Y - 0.001, (-0.3, 0.3), 1.2
    if gable is not None:
        if shell > 0 or panel > 0 or door > 0 or corridor > 0 or bend or split is not None:
            raise ValueError("a gable roof goes with rooms of one polygon, without slabs, a doorway, corridor, "
                             "cupboard, bow or split")
        if not (0 < gable < Y and -0.6 <= ridge <= 0.6):
            raise ValueError("a gable roof needs eaves between 0 and %g m and a ridge within 0.6 m of z = 0" % Y)
        # Lamps 30 cm deep under the ridge, 20 cm under the roof; the
        # camera 25 cm below them, so that it never sees a lamp's dark top.
        lamp_z = (ridge - 0.15, ridge + 0.15)
        lamp_y = min(roof_height(lamp_z[0], gable, ridge), roof_height(lamp_z[1], gable, ridge)) - 0.2
        eye_y = min(eye_y, lamp_y - 0.25)
        gable_rooms(room, shared, gable, ridge, thickness)
    elif shell > 0:
        # Six slabs round the rooms, overlapping at the edges.
        for axis in range(3):
            for side in range(2):
                slo, shi = [c - shell for c in lo], [c + shell for c in hi]
                if side:
                    slo[axis] = hi[axis]
                else:
                    shi[axis] = lo[axis]
                box(room, tuple(slo), tuple(shi))
    else:
        box(room, lo, hi, inward=True)
    # The wall in pieces round the doorway (one piece without one):
    # (z0, z1, y0) spans, full height from y0.
    pieces = [(-Z, DOOR_Z, 0.0), (DOOR_Z + door, Z, 0.0), (DOOR_Z, DOOR_Z + door, DOOR_TOP)] if door > 0 \
        else [(-Z, Z, 0.0)]
    walls = [] if gable is not None else [WALL_X] + ([WALL_X + corridor] if corridor > 0 else [])
    if bend:
        if thickness > 0 or door > 0 or corridor > 0:
            raise ValueError("a bowed wall is one polygon, without a doorway or corridor")
        bowed_wall(shared, bend, bend_rows)
        walls = []
    for x in walls:
        for z0, z1, y0 in (pieces if x == WALL_X else [(-Z, Z, 0.0)]):
            if thickness > 0:
                box(shared, (x - thickness / 2, y0, z0), (x + thickness / 2, Y, z1))
            else:
                if back_to_back and x == WALL_X:
                    shared.quad([(x, y0, z1), (x, Y, z1), (x, Y, z0), (x, y0, z0)], (-1.0, 0.0, 0.0))
                else:
                    shared.quad([(x, y0, z0), (x, Y, z0), (x, Y, z1), (x, y0, z1)], (1.0, 0.0, 0.0))
    if split is not None:
        if panel > 0 or corridor > 0 or bend or not -0.45 <= split <= -0.1:
            raise ValueError("a split is a wall at z = -0.45 to -0.1, without a cupboard, corridor or bow")
        x0 = WALL_X + thickness / 2
        if thickness > 0:
            box(shared, (x0, 0.0, split - thickness / 2), (X, Y, split + thickness / 2))
        else:
            shared.quad([(x0, 0.0, split), (X, 0.0, split), (X, Y, split), (x0, Y, split)], (0.0, 0.0, 1.0))
    if panel > 0:
        x0 = (walls[-1] if walls else WALL_X + bend) + thickness / 2
        box(room, (x0, 0.0, -0.5), (x0 + panel, 0.9, 0.5))
    meshes = [room, shared]
    if sun:
        # Ground round the building, 1.5 m wide, for the sun to light:
        # outside the walls, in cells the walls cut.
        ground, ex, ez, w = Mesh("ground", WHITE), X + shell, Z + shell, 1.5
        for x0, x1, z0, z1 in ((-ex - w, ex + w, -ez - w, -ez), (-ex - w, ex + w, ez, ez + w),
                               (-ex - w, -ex, -ez, ez), (ex, ex + w, -ez, ez)):
            ground.quad([(x0, 0.0, z0), (x1, 0.0, z0), (x1, 0.0, z1), (x0, 0.0, z1)], (0.0, 1.0, 0.0))
        meshes.append(ground)
    for name, mat, x0, x1 in (("dim lamp", DIM, 1.0, 1.6), ("bright lamp", BRIGHT, -1.4, -0.8)):
        if mat == BRIGHT and bright_light != "area":
            continue
        lamp = Mesh(name, mat)
        z0, z1 = lamp_z
        lamp.quad([(x0, lamp_y, z0), (x1, lamp_y, z0), (x1, lamp_y, z1), (x0, lamp_y, z1)],
                  (0.0, -1.0, 0.0))
        meshes.append(lamp)
    if split is not None:
        # The split-off room's lamp, as bright as the bright room's.
        lamp, z0, z1 = Mesh("split-off lamp", BRIGHT), (split - Z) / 2 - 0.12, (split - Z) / 2 + 0.12
        lamp.quad([(1.0, Y - 0.001, z0), (1.6, Y - 0.001, z0), (1.6, Y - 0.001, z1), (1.0, Y - 0.001, z1)],
                  (0.0, -1.0, 0.0))
        meshes.append(lamp)
    yaw, pitch = math.radians(yaw), math.radians(pitch)
    for m in meshes:
        m.positions = [tuple(scale * c for c in turn(p, yaw, pitch)) for p in m.positions]
    aim = look_at_point if look_at_point is not None else (walls[-1] if walls else WALL_X, 1.1, 0.0)
    eye, target = turn((1.9, eye_y, 0.0), yaw, pitch), turn(aim, yaw, pitch)
    eye, target = tuple(scale * c for c in eye), tuple(scale * c for c in target)
    camera = {"yfov": math.radians(fov_deg), "aspect": 1.0, "translation": list(eye), "rotation": look_at(eye, target),
              "znear": 0.01 * scale}
    doc, blob = gltf_document([flat_arrays(m) for m in meshes], materials, camera, "lvcl scenes/make_two_rooms.py",
                              note="two closed rooms sharing a %g m wall at x = %g%s; lamps %g (camera's room) and "
                              "%g (%s)" % (thickness * scale, WALL_X * scale,
                                           ", a doorway %g m wide" % (door * scale) if door > 0 else "", dim_le,
                                           bright_le, bright_light))
    lights = []
    rgb = (1.0, 0.0, 0.0) if colours else (1.0, 1.0, 1.0)
    if bright_light != "area":
        # The ceiling lamp's power (radiance x area x pi) from a point: intensity = power / (4 pi) W/sr.
        light = {"name": "bright %s" % bright_light, "type": bright_light, "color": list(rgb),
                 "intensity": bright_le * 0.36 * scale * scale / 4.0}
        if bright_light == "spot":
            light["spot"] = {"innerConeAngle": 0.0, "outerConeAngle": math.radians(60.0)}
        at = turn((-1.1, lamp_y - 0.049, sum(lamp_z) / 2), yaw, pitch)
        node = {"name": "bright light", "translation": [scale * c for c in at]}
        if bright_light == "spot":
            # A light shines down its node's -z: -90 degrees about x points it down, then the scene's turn.
            h = math.sqrt(0.5)
            node["rotation"] = quat_mul(quat_mul((math.sin(pitch / 2), 0.0, 0.0, math.cos(pitch / 2)),
                                                 (0.0, math.sin(yaw / 2), 0.0, math.cos(yaw / 2))), (-h, 0.0, 0.0, h))
        lights.append((light, node))
    if sun and bright_on:
        # Sunlight on the building's outside and the ground round it
        # (irradiance pi x the bright lamp's radiance), down and across at a
        # slant; the rooms are closed.
        d = turn((0.45, -0.75, 0.48), yaw, pitch)
        n = math.sqrt(sum(c * c for c in d))
        light = {"name": "sun", "type": "directional", "color": list(rgb), "intensity": math.pi * bright_le}
        lights.append((light, {"name": "sun", "rotation": look_at((0.0, 0.0, 0.0), tuple(c / n for c in d))}))
    for k, (light, node) in enumerate(lights):
        node["extensions"] = {"KHR_lights_punctual": {"light": k}}
        doc["nodes"].append(node)
        doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    if lights:
        doc["extensionsUsed"] = sorted(set(doc["extensionsUsed"]) | {"KHR_lights_punctual"})
        doc["extensions"] = {"KHR_lights_punctual": {"lights": [light for light, _ in lights]}}
    write_gltf_file(path, doc, blob)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--thickness", type=float, default=0.02, help="wall thickness, metres (0: one polygon)")
    ap.add_argument("--ratio", type=float, default=25.0, help="bright lamp radiance over the dim one's")
    ap.add_argument("--bright-off", action="store_true", help="the bright room's lamp emits nothing")
    ap.add_argument("--dim-off", action="store_true", help="the camera's room's lamp emits nothing")
    ap.add_argument("--colours", action="store_true", help="bright lamp red, dim lamp blue: red in the dim room is a leak")
    ap.add_argument("--shell", type=float, default=0.0,
                    help="outer walls, floor and ceiling as slabs this thick, metres (0: one polygon each)")
    ap.add_argument("--panel", type=float, default=0.0,
                    help="a cupboard this deep against the wall in the camera's room, metres (0: none)")
    ap.add_argument("--door", type=float, default=0.0,
                    help="a doorway this wide (2 m tall) in the (first) wall, metres (0: none)")
    ap.add_argument("--corridor", type=float, default=0.0,
                    help="a second wall like the first this far into the camera's room, metres, "
                         "leaving a corridor between the rooms, lit only through a --door (0: none)")
    ap.add_argument("--back-to-back", action="store_true",
                    help="with --corridor and --thickness 0: the first wall faces the bright room, so the two "
                         "polygons stand back to back round the corridor, as a solid's faces would")
    ap.add_argument("--yaw", type=float, default=0.0, help="the scene turned about y, degrees")
    ap.add_argument("--pitch", type=float, default=0.0, help="then about x, degrees")
    ap.add_argument("--scale", type=float, default=1.0, help="every length times this (the image stays the same)")
    ap.add_argument("--wall-material", choices=("lambert", "glossy", "mirror"), default="lambert",
                    help="the shared wall(s): lambert, glossy (plastic, roughness 0.3) or mirror")
    ap.add_argument("--bright-light", choices=("area", "point", "spot"), default="area",
                    help="the bright room's light: the ceiling lamp, or a point or spot light of its power")
    ap.add_argument("--bend", type=float, default=0.0,
                    help="the shared wall, of one polygon, bowed this far into the camera's room (metres)")
    ap.add_argument("--bend-rows", type=int, default=1, help="rows of quads of the bowed wall")
    ap.add_argument("--sun", action="store_true",
                    help="also a sun (a directional light, the bright lamp's colour, on with it) on the building's "
                         "outside and on ground 1.5 m wide round it")
    ap.add_argument("--split", type=float, default=None, metavar="Z",
                    help="a wall like the shared one across the camera's side at z = Z (-0.45 to -0.1), a third lamp "
                         "as bright as the bright one beyond it: the walls meet in a T")
    ap.add_argument("--gable", type=float, default=None, metavar="EAVES",
                    help="the rooms under a gable roof, its eaves this high (metres) and its ridge at %g m; rooms of "
                         "one polygon, without --shell, --door, --corridor, --panel, --bend or --split" % Y)
    ap.add_argument("--ridge", type=float, default=0.0, metavar="Z",
                    help="with --gable: the ridge over z = Z (-0.6 to 0.6)")
    ap.add_argument("--look-at", default=None, metavar="X,Y,Z",
                    help="where the camera looks, in the rooms' own frame (before --yaw, --pitch and --scale; default "
                         "the middle of the wall)")
    ap.add_argument("--fov", type=float, default=70.0,
                    help="the camera's vertical field of view, degrees (a tiny one zooms onto --look-at)")
    a = ap.parse_args()
    if a.bend and (a.thickness > 0 or a.door > 0 or a.corridor > 0):
        ap.error("--bend makes the wall one polygon: use it with --thickness 0 and no --door or --corridor")
    if a.bend_rows < 1:
        ap.error("--bend-rows must be at least 1")
    if a.scale <= 0:
        ap.error("--scale must be positive")
    look = None
    if a.look_at is not None:
        try:
            look = tuple(float(c) for c in a.look_at.split(","))
        except ValueError:
            look = ()
        if len(look) != 3:
            ap.error("--look-at expects three numbers X,Y,Z, not '%s'" % a.look_at)
    if a.split is not None and (a.panel > 0 or a.corridor > 0 or a.bend or not -0.45 <= a.split <= -0.1):
        ap.error("--split expects a z from -0.45 to -0.1, without --panel, --corridor or --bend")
    if a.gable is not None and (a.shell > 0 or a.door > 0 or a.corridor > 0 or a.panel > 0 or a.bend or
                                a.split is not None):
        ap.error("--gable goes with rooms of one polygon: not with --shell, --door, --corridor, --panel, --bend "
                 "or --split")
    if a.gable is not None and not (0 < a.gable < Y and -0.6 <= a.ridge <= 0.6):
        ap.error("--gable expects eaves between 0 and %g m, --ridge a z from -0.6 to 0.6" % Y)
    if not 0 < a.fov < 180:
        ap.error("--fov must be between 0 and 180 degrees")
    if a.bright_off and a.dim_off:
        ap.error("--bright-off and --dim-off together leave the scene dark")
    two_rooms(a.out, a.thickness, a.ratio, not a.bright_off, a.colours, a.shell, a.panel, a.yaw, a.pitch, a.door,
              not a.dim_off, a.corridor, a.back_to_back, a.scale, a.wall_material, a.bright_light, a.bend,
              a.bend_rows, look, a.fov, a.split, a.sun, a.gable, a.ridge)


if __name__ == "__main__":
    main()
