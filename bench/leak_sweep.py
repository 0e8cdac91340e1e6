#!/usr/bin/env python3
"""Random two-room set-ups against the light volume's leak test (issue 12):
each draws a wall (one polygon to 20 cm), outer walls of one polygon or of
slabs, a cupboard against the wall or none, a turn of the whole scene, a
grid (12 to 40 cells, any offset), --subcells and a brightness ratio (with
--wide also the scale, the wall's material and the bright light's kind;
with --curved a third of the set-ups bow a wall of one polygon; with
--tees half of those without a cupboard, corridor or bow add a wall across
the dim room's side that ends against the shared one, a third room lit as
brightly beyond it; with --edges half of them zoom the camera onto a line
where the wall meets another surface); the
bright lamp is red and the dim one blue, so any red in the dim room is the
bright room's light read through the wall (its true value, and the path
tracer's, is 0).

    python3 bench/leak_sweep.py [--seed S] [--count N] [--corridors] [--wide] [--curved] [--tees] [--edges] [--bias]
        [--corners] [--sun] [--gables] [--subcells K] [--cells C] [--build build]

One JSON object per set-up (its parameters, the dim room's mean red and
blue, leak = red / (ratio x blue) and red / blue, the share of the dim
room's light that came through the wall), then a summary: how many leaked
(leak >= 1e-4 or red / blue >= 0.03, the bounds of
tests/volume/test_two_rooms.c: the first alone would allow red / blue up
to 0.1 at 1000:1, and issue 12 asks for the dim room's mean within 3%)
and the worst. A set-up that leaked is rendered by the path tracer too (64
samples): its red, pt_red, tells light that really passes (a crack where
walls meet, a ray started beyond a surface) from the volume's mixing of
the two sides; the summary counts those as leaked_in_pt_too.
Set-ups draw 10^5 particles and 4 samples of a 32 x 32 image: a leak is
there or not, and shows at that count. Takes about a second a set-up.

With --bias each set-up is also rendered at 10^6 particles and 16
samples, and by the path tracer at 256: the dim room's blue, its own
light, must agree (lv_over_pt; the summary counts set-ups more than 2%
apart), and in the room views so must each 8 x 8-pixel block, within 10%
(lv_over_pt_blocks: the least and largest block ratio; blocks_biased).
That found a thin wall's face just inside a subcell reading its room
5-11% dark (docs/light-volume.md, "A face by a subcell's face"). About
six seconds a set-up. --subcells K renders every set-up with K subcells
and --cells C with C cells along the longest axis (the draws stay as they
were); --gables puts a third of the set-ups' rooms, of one polygon, under
a gable roof; --corners looks at a corner of the dim
room in half the set-ups (where slabs of a turned shell meet; an ad-hoc
sweep of such views found corners 0.88-0.95 in 8 x 8 blocks without
subcells before 2026-12-07)."""
import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes"))
from make_two_rooms import WALL_X, Y, Z, roof_height, two_rooms  # noqa: E402

LEAK = 1e-4
# And at most this share of the dim room's own light, whatever the ratio:
# issue 12 asks the dim room's mean to stay within 3% with the bright light
# on and off, which LEAK alone allows up to 10% at 1000:1.
SHARE = 0.03
BIAS = 0.02
# A view zoomed onto the line where two surfaces meet (--edges) reads the
# light volume at that line itself, where the true light dips within a few
# centimetres of the corner and a cell's average cannot follow it
# (docs/light-volume.md, "Corner lines"); such views are counted apart, to
# a bound that measures that limit rather than hides it.
EDGE_BIAS = 0.1
# The room views' 8 x 8-pixel blocks (16 of a 32 x 32 image), lv's over the
# path tracer's: a corner a cell's region reads too dark hides in the
# image's mean (a slab corner's block 0.88 in an image 0.994). Where lv is
# right, noise and the lookups' blur keep blocks within about 5% (0.951-1.046
# over the 12 set-ups of --wide --corridors --curved --tees --seed 70), and
# the path tracer's noise off a mirror wall once within 8% (1.079, seed 71
# with --subcells 0; 1.024 at 2048 samples).
BLOCK_BIAS = 0.1


def draw(r, corridors):
    u = {
        "wall_m": r.choice([0.0, 0.005, 0.02, 0.03, 0.06, 0.1, 0.2]),
        "slabs_m": r.choice([0.0, 0.0, 0.02, 0.05, 0.1, 0.3]),
        "cupboard_m": r.choice([0.0, 0.0, 0.03, 0.05, 0.3]),
        "yaw_deg": r.choice([0.0, round(r.uniform(0, 90), 1)]),
        "pitch_deg": r.choice([0.0, round(r.uniform(0, 30), 1)]),
        "cells": r.choice([12, 16, 20, 24, 32, 40]),
        "grid_offset": r.choice([0.0, 0.37, 0.5, round(r.random() * 0.99, 2)]),
        "subcells": r.choice([0, 2, 3, 4, 4]),
        "ratio": r.choice([25, 1000]),
        "corridor_m": r.choice([0.0, 0.0, 0.03, 0.1, 0.15, 0.4]) if corridors else 0.0,
    }
    u["door_m"] = r.choice([0.0, 0.6]) if u["corridor_m"] > 0 else 0.0
    u["back_to_back"] = u["corridor_m"] > 0 and u["wall_m"] == 0 and r.random() < 0.5
    return u


def draw_wide(r):
    """The draws of --wide, from their own stream (a seed's other draws stay
    as they were): the scene's scale, the shared wall's material and the
    bright room's light (a spot only where the scene is not turned)."""
    return {
        "scale": r.choice([1.0, 1.0, 0.01, 0.1, 10.0, 100.0]),
        "wall_material": r.choice(["lambert", "glossy", "mirror"]),
        "bright_light": r.choice(["area", "point", "spot"]),
    }


def draw_curved(r):
    """The draws of --curved, from their own stream: whether the shared
    wall is bowed (one polygon, 10-60 cm into the dim room, one or five
    rows of quads)."""
    bowed = r.random() < 1 / 3
    return {"bend_m": round(r.uniform(0.1, 0.6), 2) if bowed else 0.0, "bend_rows": r.choice([1, 5])}


def compare(build, exr, reference):
    """build/lvcl-compare's report of exr against reference."""
    text = subprocess.run([os.path.join(build, "lvcl-compare"), exr, reference], check=True, capture_output=True,
                          text=True).stdout
    return json.loads(text)


def dim_room_mean(build, exr):
    """The image's mean (r, g, b), as build/lvcl-compare reports it."""
    return compare(build, exr, exr)["mean"]


def draw_tee(r, u):
    """The draws of --tees, from their own stream: in half the set-ups
    without a cupboard, corridor or bow, a wall across the dim room's side
    at z = -0.45 to -0.1 (make_two_rooms.py --split)."""
    free = not u["cupboard_m"] and not u["corridor_m"] and not u.get("bend_m", 0.0)
    split = round(r.uniform(-0.45, -0.1), 3) if r.random() < 0.5 else None
    return {"split_z": split if free else None}


def draw_edges(r, u):
    """The draws of --edges, from their own stream: in half the set-ups a
    point on a line where the camera's face of the shared wall meets the
    floor, the ceiling or a side wall, or where the cupboard meets the wall
    or ends (in the rooms' own frame), for a camera zoomed onto it (a field
    of view of 1e-5 degrees: every pixel within a few hundred nanometres of
    the line, where a surface point lies on both surfaces' planes)."""
    if r.random() < 0.5:
        return {"look_at": None}
    def face(z):
        bend = u.get("bend_m", 0.0)
        if bend:
            return WALL_X + bend * math.cos(math.pi * z / (2 * Z))
        return WALL_X + u["corridor_m"] + u["wall_m"] / 2
    z, y = round(r.uniform(-0.9, 0.9), 3), round(r.uniform(0.1, Y - 0.1), 3)
    lines = [(face(z), 0.0, z), (face(z), Y, z), (face(Z), y, Z), (face(-Z), y, -Z)]
    if u.get("split_z") is not None:
        # Where the split-off room's wall ends against the shared one, twice the odds.
        lines += [(face(0.0), y, u["split_z"] + u["wall_m"] / 2)] * 2
    if u["cupboard_m"] > 0 and not u.get("bend_m", 0.0):
        x0, top = face(0.0), 0.9
        lines += [(x0, round(r.uniform(0.05, top - 0.05), 3), 0.5), (x0 + u["cupboard_m"], top, z / 2)]
    return {"look_at": [round(c, 6) for c in r.choice(lines)]}


def draw_corner(r, u):
    """The draws of --corners, from their own stream: in half the set-ups
    without an --edges view, a 40-degree view onto a corner of the dim
    room, where the shared wall or the far wall meets the floor or the
    ceiling and a side wall (slabs meet there at a slant when the scene is
    turned)."""
    if u.get("look_at") or r.random() < 0.5:
        return {"corner": None}
    x = round(r.uniform(WALL_X + u["corridor_m"] + u["wall_m"] / 2, 1.9), 3)
    return {"corner": [x, r.choice([0.0, Y]), r.choice([-Z, Z])]}


def draw_gable(r):
    """The draws of --gables, from their own stream: in a third of the
    set-ups a gable roof over rooms of one polygon (make_two_rooms.py
    --gable, --ridge), which then have no slabs, cupboard, corridor, bow or
    split: eaves 0.15 to 1.3 m high, the ridge over the middle or off it,
    the roof 37 to 80 degrees steep."""
    eaves, ridge = r.choice([0.15, 0.4, 0.8, 1.3]), r.choice([0.0, 0.0, 0.35, -0.6])
    if r.random() >= 1 / 3:
        return {"gable_m": None}
    return {"gable_m": eaves, "ridge_z": ridge, "slabs_m": 0.0, "cupboard_m": 0.0, "corridor_m": 0.0, "door_m": 0.0,
            "back_to_back": False, "bend_m": 0.0, "split_z": None}


def under_roof(u):
    """A view onto the ceiling's line, or high on a side wall, moved onto
    the roof or below the eaves of u's gable."""
    eaves, ridge, fitted = u["gable_m"], u["ridge_z"], {}
    for key in ("look_at", "corner"):
        if u.get(key):
            x, y, z = u[key]
            y = roof_height(z, eaves, ridge) if y == Y else y * eaves / Y if abs(z) == Z else y
            fitted[key] = [x, round(y, 6), z]
    return fitted


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=50)
    ap.add_argument("--build", default="build")
    ap.add_argument("--corridors", action="store_true",
                    help="also draw a second wall 3-40 cm beyond the first (a corridor between the rooms, lit through "
                         "a doorway or dark; walls of one polygon back to back or facing one way)")
    ap.add_argument("--wide", action="store_true",
                    help="also draw the scene's scale (0.01-100), the shared wall's material (lambert, glossy, mirror) "
                         "and the bright room's light (the ceiling lamp, or a point or spot light of its power)")
    ap.add_argument("--curved", action="store_true",
                    help="also bow the shared wall (one polygon, 10-60 cm, no doorway or corridor) in a third of the "
                         "set-ups")
    ap.add_argument("--tees", action="store_true",
                    help="in half the set-ups without a cupboard, corridor or bow add a wall across the dim room's side "
                         "that ends against the shared one, a room lit as brightly as the bright one beyond it")
    ap.add_argument("--bias", action="store_true",
                    help="also compare the dim room's own light, lv (10^6 particles, 16 samples) against the path "
                         "tracer (256 samples); with --edges, views of a corner line count apart (edge_biased, "
                         "against a wider bound: the volume cannot follow the light's dip at the line itself)")
    ap.add_argument("--corners", action="store_true",
                    help="in half the set-ups without an --edges view, look at a corner of the dim room (40 degrees) "
                         "instead of the shared wall; counted as room views")
    ap.add_argument("--subcells", type=int, default=None,
                    help="render every set-up with this many subcells a side (0-4) instead of the drawn count")
    ap.add_argument("--cells", type=int, default=None,
                    help="render every set-up with this many cells along the longest axis instead of the drawn count")
    ap.add_argument("--sun", action="store_true",
                    help="in a third of the set-ups add a sun of the bright lamp's colour on the building's outside "
                         "and on ground round it: the outside's light must stay out too")
    ap.add_argument("--gables", action="store_true",
                    help="in a third of the set-ups a gable roof over rooms of one polygon, without slabs, "
                         "cupboard, corridor, bow or split")
    ap.add_argument("--edges", action="store_true",
                    help="in half the set-ups zoom the camera onto a line where the wall meets the floor, the "
                         "ceiling, a side wall, the cupboard or the --tees wall")
    a = ap.parse_args()
    r, r_wide, r_curved = random.Random(a.seed), random.Random(a.seed + 1000003), random.Random(a.seed + 2000003)
    r_edges, r_tees = random.Random(a.seed + 3000017), random.Random(a.seed + 4000037)
    r_corners, r_sun = random.Random(a.seed + 5000011), random.Random(a.seed + 6000029)
    r_gables = random.Random(a.seed + 7000003)
    leaks, pt_leaks, worst, worst_share = 0, 0, 0.0, 0.0
    biased, worst_bias, edge_biased, worst_edge_bias = 0, 0.0, 0, 0.0
    blocks_biased, worst_block_bias = 0, 0.0
    with tempfile.TemporaryDirectory() as tmp:
        scene, image = os.path.join(tmp, "rooms.gltf"), os.path.join(tmp, "rooms.exr")
        for _ in range(a.count):
            u = draw(r, a.corridors)
            if a.subcells is not None:
                u["subcells"] = a.subcells
            if a.cells is not None:
                u["cells"] = a.cells
            wide = draw_wide(r_wide) if a.wide else {"scale": 1.0, "wall_material": "lambert", "bright_light": "area"}
            if wide["bright_light"] == "spot" and (u["yaw_deg"] or u["pitch_deg"]):
                wide["bright_light"] = "point"
            if a.wide:
                u.update(wide)
            curved = draw_curved(r_curved) if a.curved else {"bend_m": 0.0, "bend_rows": 1}
            if curved["bend_m"]:
                u.update(curved, wall_m=0.0, corridor_m=0.0, door_m=0.0, back_to_back=False)
            if a.tees:
                u.update(draw_tee(r_tees, u))
            if a.gables:
                u.update(draw_gable(r_gables))
                if u["gable_m"]:
                    curved = {"bend_m": 0.0, "bend_rows": 1}
            if a.edges:
                u.update(draw_edges(r_edges, u))
            if a.corners:
                u.update(draw_corner(r_corners, u))
            u["sun"] = a.sun and r_sun.random() < 1 / 3
            if u.get("gable_m"):
                u.update(under_roof(u))
            with open(os.devnull, "w") as quiet:
                saved, sys.stdout = sys.stdout, quiet
                try:
                    two_rooms(scene, u["wall_m"], u["ratio"], True, colours=True, shell=u["slabs_m"],
                              panel=u["cupboard_m"], yaw=u["yaw_deg"], pitch=u["pitch_deg"], corridor=u["corridor_m"],
                              door=u["door_m"], back_to_back=u["back_to_back"], scale=wide["scale"],
                              wall_material=wide["wall_material"], bright_light=wide["bright_light"],
                              bend=curved["bend_m"], bend_rows=curved["bend_rows"],
                              look_at_point=u.get("look_at") or u.get("corner"),
                              fov_deg=1e-5 if u.get("look_at") else 40.0 if u.get("corner") else 70.0,
                              split=u.get("split_z"), sun=u["sun"], gable=u.get("gable_m"),
                              ridge=u.get("ridge_z", 0.0))
                finally:
                    sys.stdout = saved
            grid = ["--cells", str(u["cells"]), "--grid-offset", str(u["grid_offset"]), "--subcells", str(u["subcells"])]
            subprocess.run([os.path.join(a.build, "lvcl"), "-q", "--mode", "lv"] + grid +
                           ["--particles", "1e5", "--spp", "4", "--width", "32", "--height", "32", "--seed", "5",
                            "-o", image, scene], check=True)
            red, _, blue = dim_room_mean(a.build, image)
            u["red"], u["blue"] = red, blue
            u["leak"] = red / (u["ratio"] * blue) if blue > 0 else float("inf")
            u["red_over_blue"] = red / blue if blue > 0 else float("inf")
            leaked = u["leak"] >= LEAK or u["red_over_blue"] >= SHARE
            leaks += leaked
            if leaked:
                # The path tracer on the same scene: red there too means the
                # light really passes (a crack in the geometry, or rays that
                # start beyond a surface), not that the volume mixes sides.
                subprocess.run([os.path.join(a.build, "lvcl"), "-q", "--mode", "pt", "--spp", "64", "--width", "32",
                                "--height", "32", "--seed", "5", "-o", image, scene], check=True)
                u["pt_red"] = dim_room_mean(a.build, image)[0]
                pt_leaks += u["pt_red"] > 0
            if a.bias:
                images = []  # lv then pt
                for mode, extra in (("lv", grid + ["--particles", "1e6", "--spp", "16"]), ("pt", ["--spp", "256"])):
                    images.append(os.path.join(tmp, mode + ".exr"))
                    subprocess.run([os.path.join(a.build, "lvcl"), "-q", "--mode", mode] + extra +
                                   ["--width", "32", "--height", "32", "--seed", "5", "-o", images[-1], scene],
                                   check=True)
                report = compare(a.build, *images)
                own = report["mean"][2], report["reference_mean"][2]  # the dim room's blue, its own light
                u["lv_over_pt"] = own[0] / own[1] if own[1] > 0 else float("nan")
                off = abs(u["lv_over_pt"] - 1)
                if u.get("look_at"):
                    edge_biased += not off <= EDGE_BIAS
                    worst_edge_bias = max(worst_edge_bias, off)
                else:
                    biased += not off <= BIAS
                    worst_bias = max(worst_bias, off)
                    u["lv_over_pt_blocks"] = report["block_ratios"]
                    block_off = max(abs(x - 1) for x in u["lv_over_pt_blocks"])
                    blocks_biased += not block_off <= BLOCK_BIAS
                    worst_block_bias = max(worst_block_bias, block_off)
            worst = max(worst, u["leak"])
            worst_share = max(worst_share, u["red_over_blue"])
            print(json.dumps(dict({"bench": "leak_sweep"}, **u)), flush=True)
    print(json.dumps(dict({"bench": "leak_sweep", "summary": True, "setups": a.count, "leaked": leaks,
                      "leaked_in_pt_too": pt_leaks,
                      "worst_leak": worst, "bound": LEAK, "worst_red_over_blue": worst_share,
                      "share_bound": SHARE},
                     **({"biased": biased, "bias_bound": BIAS, "worst_bias": worst_bias,
                         "blocks_biased": blocks_biased, "block_bias_bound": BLOCK_BIAS,
                         "worst_block_bias": worst_block_bias,
                         "edge_biased": edge_biased, "edge_bias_bound": EDGE_BIAS,
                         "worst_edge_bias": worst_edge_bias} if a.bias else {}))))


if __name__ == "__main__":
    main()
