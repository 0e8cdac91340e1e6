#!/usr/bin/env python3
"""lvcl's path tracer against Mitsuba 3's at equal samples per pixel, in one
run on one machine: both render the same glTF scenes, each image is measured
against the scene's reference (relMSE, build/lvcl-compare), and the times
and their ratio are printed.

    build/venv/bin/python bench/vs_mitsuba.py [--spp 256] [--width 256 --height 256]
        [--scenes cornell,glass-table,kitchen] [--build build] [--out DIR] [--seed S]
        [--lvcl-args "--see-through off"]

lvcl: `lvcl -q --mode pt --spp N`; "seconds" is its --stats render_seconds
(the kernels are built and warmed by a 1-spp render first, not counted).
Mitsuba 3 (llvm_ad_rgb where it loads, else scalar_rgb; path tracer, max
depth 64, Russian roulette from depth 5, as tests/reference/render_reference.py):
one warm-up render of 1 spp compiles its kernels, then one render of N spp
is timed, image readback included.  The scenes are scenes/NAME.gltf and their
references tests/reference/NAME.exr, rendered at the reference's size unless
--width and --height say otherwise.

One JSON object per scene: both times, both errors,
"speed_ratio" = mitsuba seconds / lvcl seconds (above 1: lvcl is faster), and
"equal_error_ratio" = (mitsuba seconds x relMSE) / (lvcl seconds x relMSE):
how much faster lvcl reaches the same error, as relMSE falls as 1/spp for both.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
sys.path.insert(0, HERE)
from budget import compare, load_mitsuba  # noqa: E402  (same folder)


def fail(message):
    print(f"vs_mitsuba: {message}", file=sys.stderr)
    sys.exit(1)


def run_lvcl(a, scene, spp, image):
    stats = image + ".stats.json"
    cmd = [os.path.join(a.build, "lvcl"), "-q", "--mode", "pt", "--spp", str(spp), "--width", str(a.width),
           "--height", str(a.height), "--seed", str(a.seed), "--stats", stats, "-o", image, scene]
    cmd[1:1] = a.lvcl_args.split()
    subprocess.run(cmd, check=True)
    with open(stats) as f:
        return json.load(f)["render_seconds"]


def run_mitsuba(mi, mscene, spp, seed, image):
    import numpy as np
    from render_reference import write_exr
    mi.render(mscene, spp=1, seed=seed + 1)  # warm-up: kernel compilation
    start = time.monotonic()
    img = np.array(mi.render(mscene, spp=spp, seed=seed), dtype=np.float64)[:, :, :3]
    seconds = time.monotonic() - start
    write_exr(image, img)
    return seconds


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--spp", type=int, default=256)
    p.add_argument("--width", type=int, default=None, help="default: the reference's")
    p.add_argument("--height", type=int, default=None, help="default: the reference's")
    p.add_argument("--scenes", default="cornell,glass-table,kitchen")
    p.add_argument("--build", default=os.path.join(ROOT, "build"))
    p.add_argument("--out", default=None, help="folder for the images (default: a temporary one)")
    p.add_argument("--seed", type=int, default=4)
    p.add_argument("--variant", default=None, help="Mitsuba variant (default: llvm_ad_rgb if it loads)")
    p.add_argument("--lvcl-args", default="", help="more lvcl flags, e.g. \"--see-through off\"")
    a = p.parse_args()
    if a.spp < 1 or (a.width or 1) < 1 or (a.height or 1) < 1:
        fail("--spp, --width and --height must be positive")
    sys.path.insert(0, os.path.join(ROOT, "tests", "reference"))
    import render_reference
    import mitsuba as mi
    render_reference.pick_variant(a.variant)
    size = (a.width, a.height)
    if not os.path.exists(os.path.join(a.build, "lvcl")):
        fail(f"no {a.build}/lvcl: run make first")
    out = a.out or tempfile.mkdtemp(prefix="vs_mitsuba_")
    os.makedirs(out, exist_ok=True)
    for name in a.scenes.split(","):
        gltf = os.path.join(ROOT, "scenes", name + ".gltf")
        ref = os.path.join(ROOT, "tests", "reference", name + ".exr")
        if not os.path.exists(gltf) or not os.path.exists(ref):
            fail(f"scene {name}: needs {gltf} and {ref}")
        a.width, a.height = size[0] or mi.Bitmap(ref).size()[0], size[1] or mi.Bitmap(ref).size()[1]
        lv_img = os.path.join(out, f"{name}.lvcl.exr")
        run_lvcl(a, gltf, 1, lv_img)  # kernel build and first-launch compiles
        lv_s = run_lvcl(a, gltf, a.spp, lv_img)
        a.scene = gltf
        a.pass_spp = a.spp
        with tempfile.TemporaryDirectory() as work:
            mi, mscene, variant, _ = load_mitsuba(a, work)  # the same module, scene converted
            mi_img = os.path.join(out, f"{name}.mitsuba.exr")
            mi_s = run_mitsuba(mi, mscene, a.spp, a.seed, mi_img)
        lv_e, mi_e = compare(a.build, lv_img, ref)["relmse"], compare(a.build, mi_img, ref)["relmse"]
        print(json.dumps({"scene": name, "spp": a.spp, "width": a.width, "height": a.height,
                          "lvcl_seconds": round(lv_s, 3), "mitsuba_seconds": round(mi_s, 3),
                          "mitsuba_variant": variant, "lvcl_relmse": lv_e, "mitsuba_relmse": mi_e,
                          "speed_ratio": round(mi_s / lv_s, 3),
                          "equal_error_ratio": round(mi_s * mi_e / (lv_s * lv_e), 3)}), flush=True)


if __name__ == "__main__":
    main()
