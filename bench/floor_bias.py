#!/usr/bin/env python3
"""The glass table's floor under the light volume (docs/light-volume.md,
"What no split reaches: the glass table's floor"): the mean of lv images
over two floor regions and over the whole image, divided by the same of
lvcl's own path tracer at many samples, for each set of extra lvcl
arguments given. 1.000 is unbiased; the path tracer agrees with the
Mitsuba reference there.

    build/venv/bin/python bench/floor_bias.py [--build build] [--ior X]
        [--particles 4e6] [--spp 128] [--pt-spp 2048] [--size 128]
        [--runs "--dirs 4" "--dirs 8" "--cells 64" ...]

--ior X renders a copy of scenes/glass-table.gltf whose glass has that
index of refraction (1.01: glass all but invisible, which still blocks
shadow rays). Regions, as fractions of the image (rows, columns): the
open floor at the bottom right, in front of the table (rows 88-127,
columns 96-127 of 128 x 128) and the floor under the table's far half
(rows 64-71, columns 24-55). Prints one JSON object per run.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import mitsuba as mi
import numpy as np

REGIONS = {"open_floor": (88, 128, 96, 128), "under_table": (64, 72, 24, 56)}  # of 128 x 128


def render(build, args, out):
    cmd = [os.path.join(build, "lvcl"), "-q", "-o", out] + args
    if subprocess.run(cmd).returncode != 0:
        sys.exit("floor_bias: %s failed" % " ".join(cmd))
    return np.array(mi.Bitmap(out))[..., :3]


def means(image, size):
    s = size / 128.0
    m = {name: image[int(r0 * s):int(r1 * s), int(c0 * s):int(c1 * s)].mean()
         for name, (r0, r1, c0, c1) in REGIONS.items()}
    m["image"] = image.mean()
    return m


def scene_with_ior(ior, folder):
    """A copy of the glass table whose glass material has this ior."""
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "..", "scenes", "glass-table.gltf")) as f:
        gltf = json.load(f)
    for m in gltf["materials"]:
        if "KHR_materials_transmission" in m.get("extensions", {}):
            m["extensions"]["KHR_materials_ior"] = {"ior": ior}
    path = os.path.join(folder, "glass-table-ior.gltf")
    with open(path, "w") as f:
        json.dump(gltf, f)
    return path


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build")
    p.add_argument("--ior", type=float)
    p.add_argument("--particles", default="4e6")
    p.add_argument("--spp", default="128")
    p.add_argument("--pt-spp", default="2048")
    p.add_argument("--size", type=int, default=128)
    p.add_argument("--runs", nargs="*", default=[""])
    a = p.parse_args()
    mi.set_variant("scalar_rgb")
    with tempfile.TemporaryDirectory() as tmp:
        here = os.path.dirname(os.path.abspath(__file__))
        scene = scene_with_ior(a.ior, tmp) if a.ior else os.path.join(here, "..", "scenes", "glass-table.gltf")
        size = ["--width", str(a.size), "--height", str(a.size)]
        ref = means(render(a.build, ["--mode", "pt", "--spp", a.pt_spp, "--seed", "5"] + size + [scene],
                           os.path.join(tmp, "pt.exr")), a.size)
        for extra in a.runs:
            args = ["--mode", "lv", "--particles", a.particles, "--spp", a.spp, "--seed", "4"] + size + extra.split()
            m = means(render(a.build, args + [scene], os.path.join(tmp, "lv.exr")), a.size)
            print(json.dumps({"args": " ".join(args), "ior": a.ior,
                              **{k: round(float(m[k] / ref[k]), 4) for k in m}}), flush=True)


if __name__ == "__main__":
    main()
