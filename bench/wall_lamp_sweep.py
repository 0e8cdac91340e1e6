#!/usr/bin/env python3
"""A lamp mounted a hair in front of a wall, against the light volume's leak
test (issue 12): a room (4 x 2.5 x 2 m) split by a wall at x = 0.37, of one
polygon or 2 cm thick; a blue ceiling lamp in the room x > 0.37, where the
camera stands; a red square lamp 1000 times as bright in the other room,
0.5 to 5 mm in front of the wall, 10 to 60 cm across, low, in the middle
or high, shining at the wall or away from it. No red may reach the camera
(the path tracer's red is 0). Each lamp is rendered on three grids (16,
32 and 40 cells at offsets 0, 0.37 and 0.5), 10^5 particles, 4 samples of
32 x 32: 144 renders, about two minutes.

    python3 bench/wall_lamp_sweep.py [--build build]

One JSON object per render that showed red, then a summary (renders, how
many showed red, the worst red / blue). The build before 2026-12-07 took
the wall's back, a pocket closed by the lamp 2 mm away, for dark: 15 of
144 showed red, up to red / blue 3.7 (docs/light-volume.md, "A lamp
shining at a wall a hair away")."""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes"))
from make_scenes import Mesh, box, emission, flat_arrays, gltf_document, lambert, look_at  # noqa: E402
from sweep_common import image_mean, write_quietly  # noqa: E402

WALL_X = 0.37


def write_scene(path, gap, size, height, facing, thickness):
    """The two rooms, the wall, the blue lamp and the red one `gap` in front of the wall."""
    dim_factor, dim_strength = emission((0.0, 0.0, 3.0))
    red_factor, red_strength = emission((3000.0, 0.0, 0.0))
    materials = [lambert("white", (0.7, 0.7, 0.7)),
                 lambert("dim lamp", (0.0, 0.0, 0.0), emissive=dim_factor, strength=dim_strength),
                 lambert("wall lamp", (0.0, 0.0, 0.0), emissive=red_factor, strength=red_strength)]
    room, wall, dim, lamp = Mesh("room", 0), Mesh("wall", 0), Mesh("dim lamp", 1), Mesh("wall lamp", 2)
    box(room, (-2.0, 0.0, -1.0), (2.0, 2.5, 1.0), inward=True)
    if thickness > 0:
        box(wall, (WALL_X - thickness / 2, 0.0, -1.0), (WALL_X + thickness / 2, 2.5, 1.0))
    else:
        wall.quad([(WALL_X, 0.0, -1.0), (WALL_X, 2.5, -1.0), (WALL_X, 2.5, 1.0), (WALL_X, 0.0, 1.0)], (1.0, 0.0, 0.0))
    dim.quad([(1.0, 2.499, -0.3), (1.6, 2.499, -0.3), (1.6, 2.499, 0.3), (1.0, 2.499, 0.3)], (0.0, -1.0, 0.0))
    x, s = WALL_X - thickness / 2 - gap, size / 2
    lamp.quad([(x, height - s, -s), (x, height + s, -s), (x, height + s, s), (x, height - s, s)], (facing, 0.0, 0.0))
    eye, target = (1.9, 1.2, 0.0), (WALL_X, 1.1, 0.0)
    camera = {"yfov": math.radians(70.0), "aspect": 1.0, "translation": list(eye), "rotation": look_at(eye, target),
              "znear": 0.01}
    doc, blob = gltf_document([flat_arrays(m) for m in (room, wall, dim, lamp)], materials, camera,
                              "lvcl bench/wall_lamp_sweep.py", note="a red lamp %g m in front of a wall" % gap)
    write_quietly(path, doc, blob)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default="build")
    a = ap.parse_args()
    renders, red_renders, worst = 0, 0, 0.0
    with tempfile.TemporaryDirectory() as tmp:
        scene, image = os.path.join(tmp, "lamp.gltf"), os.path.join(tmp, "lamp.exr")
        for thickness in (0.0, 0.02):
            for gap in (0.0005, 0.001, 0.002, 0.005):
                for size, height in ((0.3, 1.5), (0.1, 0.3), (0.6, 2.15)):
                    for facing in (-1.0, 1.0):
                        write_scene(scene, gap, size, height, facing, thickness)
                        for cells, offset in ((16, 0.0), (32, 0.37), (40, 0.5)):
                            subprocess.run([os.path.join(a.build, "lvcl"), "-q", "--mode", "lv", "--cells", str(cells),
                                            "--grid-offset", str(offset), "--particles", "1e5", "--spp", "4",
                                            "--width", "32", "--height", "32", "--seed", "5", "-o", image, scene],
                                           check=True)
                            red, _, blue = image_mean(a.build, image)
                            renders += 1
                            if red > 0:
                                red_renders += 1
                                worst = max(worst, red / blue if blue > 0 else float("inf"))
                                print(json.dumps({"bench": "wall_lamp_sweep", "wall_m": thickness, "gap_m": gap,
                                                  "size_m": size, "height_m": height,
                                                  "facing": "wall" if facing > 0 else "room", "cells": cells,
                                                  "grid_offset": offset, "red": red, "blue": blue}), flush=True)
    print(json.dumps({"bench": "wall_lamp_sweep", "summary": True, "renders": renders, "red_renders": red_renders,
                      "worst_red_over_blue": worst}))


if __name__ == "__main__":
    main()
