#!/usr/bin/env python3
"""Which grid would serve a scene better, measured without a reference
(docs/light-volume.md, "Where one level falls short"): the blur of a light
volume of cell size h, and of h / 2, from small pilot renders of each.

    build/venv/bin/python bench/resolution_probe.py SCENE [--reference REF.exr]
        [--cells 32,64] [--particles 262144] [--spp 16] [--budget 30]
        [--width 256 --height 256] [--build build]

Per grid, two lv renders of --particles and --spp with independent seeds
(the grids' seeds differ too, so no noise is shared). Their difference
gives each image's noise n (relMSE between two images of equal bias is
twice the noise of one). The mean of each pair has noise n / 2, so

    D2 = relMSE(mean_coarse, mean_fine) - n_coarse / 2 - n_fine / 2

estimates the squared difference of the two grids' biases, mean over
pixels of (b_coarse - b_fine)^2. Where the fine grid's bias is a fraction
r of the coarse one's at each pixel (a blur over half the width), the
error the finer grid removes, b_coarse^2 - b_fine^2 = D2 (1 + r) / (1 - r),
is at least D2. What it costs at a budget of T seconds is its extra noise:
each pilot's noise times its seconds over T (noise falls as 1 / time when
particles and samples grow together). The fine grid pays where D2,
computed from each coarse image against each fine one (four pairings,
each less one image's noise of each grid), exceeds that cost in all four
("fine_pays"). The pairings' spread is the noise's alone; an error over
pixels would be too small (neighbouring pixels read the same cells) and
one over blocks would count the blur's own unevenness across the image.
The relMSE denominators are the four images' mean squared plus 0.01, as
lvcl-compare's use the reference's. With --reference, each grid's mean
image is also measured against it ("reference_relmse"), to check the
prediction. Prints one JSON object.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import mitsuba as mi
import numpy as np


def render(build, args, out, stats):
    cmd = [os.path.join(build, "lvcl"), "-q", "--mode", "lv", "--adaptive", "off", "-o", out, "--stats", stats] + args
    if subprocess.run(cmd).returncode != 0:
        sys.exit("resolution_probe: %s failed" % " ".join(cmd))
    with open(stats) as f:
        s = json.load(f)
    seconds = s.get("particle_trace_seconds", 0.0) + s.get("render_seconds", 0.0)
    return np.array(mi.Bitmap(out), dtype=np.float64)[..., :3], seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--reference", default=None)
    ap.add_argument("--cells", default="32,64", help="coarse,fine (default 32,64)")
    ap.add_argument("--particles", type=int, default=2 ** 18)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--budget", type=float, default=30.0, help="seconds the choice is for (default 30)")
    ap.add_argument("--width", type=int, default=256)
    ap.add_argument("--height", type=int, default=256)
    ap.add_argument("--build", default="build")
    a = ap.parse_args()
    mi.set_variant("scalar_rgb")
    grids = [int(c) for c in a.cells.split(",")]
    if len(grids) != 2:
        sys.exit("resolution_probe: --cells takes two counts, coarse,fine")
    images, seconds = {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        out, stats = os.path.join(tmp, "pilot.exr"), os.path.join(tmp, "stats.json")
        for g, cells in enumerate(grids):
            for k in range(2):
                args = ["--cells", str(cells), "--particles", str(a.particles), "--spp", str(a.spp),
                        "--seed", str(101 + 2 * g + k), "--width", str(a.width), "--height", str(a.height), a.scene]
                images[g, k], seconds[g, k] = render(a.build, args, out, stats)
    den = np.mean(list(images.values()), axis=0) ** 2 + 1e-2
    per_pixel = lambda x, y: ((x - y) ** 2 / den).mean(axis=-1)
    noise = [per_pixel(images[g, 0], images[g, 1]) / 2 for g in range(2)]
    means = [(images[g, 0] + images[g, 1]) / 2 for g in range(2)]
    d2 = per_pixel(means[0], means[1]) - noise[0] / 2 - noise[1] / 2
    d2_mean = float(d2.mean())
    # The same from each coarse image against each fine one: their spread is
    # the noise's alone (neighbouring pixels read the same cells, so an error
    # over pixels would be too small, and one over blocks would count the
    # blur's own unevenness across the image).
    n_mean = [float(n.mean()) for n in noise]
    pairs = [float(per_pixel(images[0, i], images[1, j]).mean()) - n_mean[0] - n_mean[1]
             for i in range(2) for j in range(2)]
    pilot_seconds = [(seconds[g, 0] + seconds[g, 1]) / 2 for g in range(2)]
    at_budget = [float(noise[g].mean()) * pilot_seconds[g] / a.budget for g in range(2)]
    result = {
        "scene": a.scene, "cells": grids, "particles": a.particles, "spp": a.spp, "budget_seconds": a.budget,
        "pilot_noise": [float(n.mean()) for n in noise], "pilot_seconds": pilot_seconds,
        "bias_difference": d2_mean, "bias_difference_pairs": pairs,
        "noise_at_budget": at_budget, "extra_noise_of_fine": at_budget[1] - at_budget[0],
        "fine_pays": min(pairs) > at_budget[1] - at_budget[0],
    }
    if a.reference:
        ref = np.array(mi.Bitmap(a.reference), dtype=np.float64)[..., :3]
        result["reference_relmse"] = [float(((m - ref) ** 2 / (ref ** 2 + 1e-2)).mean()) for m in means]
    print(json.dumps(result))


if __name__ == "__main__":
    main()
