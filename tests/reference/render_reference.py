#!/usr/bin/env python3
"""Render a glTF scene with Mitsuba 3 into a linear float32 RGB OpenEXR.

    render_reference.py SCENE OUT.exr --spp N [--width W] [--height H]
                        [--variant V] [--pass-spp P] [--seed S] [--threads T]

The scene is converted by gltf_to_mitsuba.py (lvcl's material contract).  The
image is rendered in passes of at most P samples per pixel (independent
sampler re-seeded per pass) and averaged, which bounds memory for large N.
Default variant: llvm_ad_rgb when it is available, else scalar_rgb.  The EXR
is float32 with lossless PIZ compression.  A JSON line with the timing and the
mean RGB goes to stdout.
"""

import argparse
import json
import os
import shutil
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gltf_to_mitsuba as g2m  # noqa: E402


def pick_variant(requested):
    import mitsuba as mi
    if requested:
        mi.set_variant(requested)
        return requested
    for v in ("llvm_ad_rgb", "scalar_rgb"):
        if v in mi.variants():
            try:
                mi.set_variant(v)
                return v
            except Exception:  # e.g. no libLLVM on this machine
                continue
    raise RuntimeError("no usable Mitsuba RGB variant")


def write_exr(path, img):
    import mitsuba as mi
    img = np.ascontiguousarray(img, dtype=np.float32)
    bmp = mi.Bitmap(img, pixel_format=mi.Bitmap.PixelFormat.RGB)
    tmp = path + ".tmp.exr"
    bmp.write(tmp)            # quality -1: lossless PIZ, float32 kept
    os.replace(tmp, path)


def render(scene_path, spp, width=None, height=None, variant=None,
           pass_spp=256, seed=0, max_depth=64, rr_depth=5, verbose=True):
    v = pick_variant(variant)
    import mitsuba as mi
    workdir = tempfile.mkdtemp(prefix="lvcl_ref_")
    try:
        t0 = time.time()
        d, info = g2m.convert(scene_path, width, height, spp=min(spp, pass_spp),
                              workdir=workdir, max_depth=max_depth, rr_depth=rr_depth)
        scene = mi.load_dict(d)
        t_load = time.time() - t0
        acc = None
        done, k = 0, 0
        t1 = time.time()
        while done < spp:
            n = min(pass_spp, spp - done)
            img = mi.render(scene, spp=n, seed=seed * 1000003 + k)
            img = np.array(img, dtype=np.float64)[:, :, :3]
            acc = img * n if acc is None else acc + img * n
            done += n
            k += 1
            if verbose:
                el = time.time() - t1
                print("  %d/%d spp  %.1fs" % (done, spp, el), file=sys.stderr, flush=True)
        img = (acc / spp).astype(np.float32)
        t_render = time.time() - t1
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    return img, {"variant": v, "spp": spp, "load_s": round(t_load, 3),
                 "render_s": round(t_render, 3), "width": img.shape[1],
                 "height": img.shape[0], "notes": info["notes"],
                 "materials": info["materials"]}


def main():
    ap = argparse.ArgumentParser(description="Render a glTF scene with Mitsuba 3 to EXR")
    ap.add_argument("scene")
    ap.add_argument("out")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--variant", default=None)
    ap.add_argument("--pass-spp", type=int, default=256)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--max-depth", type=int, default=64)
    ap.add_argument("--rr-depth", type=int, default=5)
    ap.add_argument("--threads", type=int, default=0, help="0: all cores")
    a = ap.parse_args()
    if a.spp < 1:
        print("render_reference: --spp must be >= 1", file=sys.stderr)
        return 2
    if a.threads > 0:
        import drjit as dr
        dr.set_thread_count(a.threads)
    try:
        img, meta = render(a.scene, a.spp, a.width, a.height, a.variant,
                           a.pass_spp, a.seed, a.max_depth, a.rr_depth)
    except (g2m.GltfError, OSError, ValueError, KeyError, RuntimeError) as e:
        print("render_reference: %s: %s" % (a.scene, e), file=sys.stderr)
        return 1
    if not np.all(np.isfinite(img)):
        print("render_reference: non-finite pixels in the result", file=sys.stderr)
        return 1
    write_exr(a.out, img)
    meta["out"] = a.out
    meta["scene"] = a.scene
    meta["mean_rgb"] = [round(float(c), 6) for c in img.reshape(-1, 3).mean(axis=0)]
    print(json.dumps(meta))
    return 0


if __name__ == "__main__":
    sys.exit(main())
