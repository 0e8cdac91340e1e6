#!/usr/bin/env python3
"""Run time against error: renders SCENE with the path tracer, guided path
tracing and the light volume over a range of budgets, measures each image against a
reference, prints one JSON object per run and plots error against time on
log-log axes (PNG, when matplotlib is available).

    bench/time_error.py SCENE REFERENCE.exr [--out DIR] [--quick] [--width W --height H]

Each run records the wall time of its parts as lvcl's --stats reports them
(scene load, BVH build, kernel build, particle trace, gather or path
tracing) and relMSE / RMSE against the reference (build/lvcl-compare).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time


def run_lvcl(build, scene, args, width, height, tmp):
    image = os.path.join(tmp, "image.exr")
    stats = os.path.join(tmp, "stats.json")
    cmd = [os.path.join(build, "lvcl"), "-q", "--width", str(width), "--height", str(height),
           "--seed", "17", "-o", image, "--stats", stats] + args + [scene]
    start = time.monotonic()
    subprocess.run(cmd, check=True)
    wall = time.monotonic() - start
    with open(stats) as f:
        s = json.load(f)
    s["wall_seconds"] = wall
    return image, s


def error(build, image, reference):
    out = subprocess.run([os.path.join(build, "lvcl-compare"), image, reference],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def flip_metric():
    """Mean HDR-FLIP through tests/reference/compare.py, when this Python has
    its packages (the venv of `make venv`); otherwise None."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "reference"))
    try:
        import compare
        import flip_evaluator  # noqa: F401  (compare.py imports it lazily)
    except ImportError:
        print("time_error: no mitsuba/flip-evaluator here, FLIP left out (run with build/venv/bin/python)",
              file=sys.stderr)
        return None
    return lambda image, reference: compare.metrics(compare.read_image(image), compare.read_image(reference))["FLIP"]


def budgets(quick):
    """(label, lvcl arguments) for every run."""
    pt_spp = [4, 16, 64] if quick else [4, 16, 64, 256, 1024]
    runs = [("pt", ["--mode", "pt", "--spp", str(s)]) for s in pt_spp]
    # Guided path tracing over a volume of 10^6 particles (docs/guided.md).
    runs += [("guided", ["--mode", "guided", "--particles", str(int(1e6)), "--spp", str(s)]) for s in pt_spp]
    # (cells, particles, subcells): the subcell estimate at several grids and
    # particle counts, and the whole-cell volume (--subcells 0) beside it.
    series = ([(16, 1e5, 4), (32, 1e6, 4), (32, 1e6, 0)] if quick else
              [(16, 1e6, 4), (32, 1e5, 4), (32, 1e6, 4), (32, 4e6, 4), (32, 1e6, 0)])
    spp = [4, 16] if quick else [16, 64, 256]
    for c, p, k in series:
        for s in spp:
            runs.append((f"lv cells={c} particles={p:.0e} subcells={k}",
                         ["--mode", "lv", "--cells", str(c), "--particles", str(int(p)), "--subcells", str(k),
                          "--spp", str(s)]))
    return runs


def plot(records, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("time_error: matplotlib not found, no plot (make venv installs it)", file=sys.stderr)
        return
    fig, ax = plt.subplots(figsize=(7, 5))
    series = {}
    for r in records:
        series.setdefault(r["label"], []).append((r["seconds"], r["relmse"]))
    # One colour per grid size, one marker per particle count.
    colours = plt.get_cmap("viridis")
    cell_sizes = sorted({r["cells"][0] for r in records if r["cells"] and r["mode"] == "lv"})
    markers = {}
    for label, pts in sorted(series.items()):
        pts.sort()
        if label in ("pt", "guided"):
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color="crimson" if label == "pt" else "darkorange",
                    linewidth=2, label=label)
            continue
        rec = next(r for r in records if r["label"] == label)
        colour = colours(cell_sizes.index(rec["cells"][0]) / max(1, len(cell_sizes) - 1))
        marker = markers.setdefault(rec["particles"], "sv^Dpx"[len(markers) % 6])
        style = ":" if label.endswith("subcells=0") else "--"
        ax.plot([p[0] for p in pts], [p[1] for p in pts], style, marker=marker, color=colour, linewidth=1,
                label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time, seconds (particle trace + rendering)")
    ax.set_ylabel("relMSE against the reference")
    ax.set_title(os.path.basename(records[0]["scene"]))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"time_error: wrote {path}", file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("reference")
    ap.add_argument("--build", default="build")
    ap.add_argument("--out", default=os.path.join("build", "bench"))
    ap.add_argument("--quick", action="store_true", help="fewer, smaller budgets")
    ap.add_argument("--width", type=int, default=256, help="image width, as the reference's (default 256)")
    ap.add_argument("--height", type=int, default=256, help="image height, as the reference's (default 256)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    error(a.build, a.reference, a.reference)  # fails early if the reference cannot be read
    flip = flip_metric()
    width, height = a.width, a.height
    records = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, args in budgets(a.quick):
            image, s = run_lvcl(a.build, a.scene, args, width, height, tmp)
            e = error(a.build, image, a.reference)
            rec = {
                "scene": a.scene, "label": label, "mode": s["mode"], "spp": s["spp"],
                "cells": s.get("grid"), "particles": s.get("particles"),
                "scene_load_seconds": s["scene_load_seconds"], "bvh_build_seconds": s["bvh_build_seconds"],
                "kernel_build_seconds": s["kernel_build_seconds"],
                "particle_trace_seconds": s.get("particle_trace_seconds", 0.0),
                "render_seconds": s["render_seconds"],
                "seconds": s.get("particle_trace_seconds", 0.0) + s["render_seconds"],
                "particles_per_second": s.get("particles_per_second"),
                "segments_per_second": s.get("segments_per_second"),
                "subcells": s.get("subcells"), "visibility_rays": s.get("visibility_rays"),
                "samples_per_second": s["samples_per_second"],
                "relmse": e["relmse"], "rmse": e["rmse"],
                "flip": flip(image, a.reference) if flip else None,
            }
            records.append(rec)
            print(json.dumps(rec), flush=True)
    stem = os.path.splitext(os.path.basename(a.scene))[0]
    plot(records, os.path.join(a.out, f"time_error_{stem}.png"))


if __name__ == "__main__":
    main()
