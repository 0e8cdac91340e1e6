#!/usr/bin/env python3
"""Equal time budgets: lvcl against Mitsuba 3's path tracer on one scene, in
one run, each image measured against a reference (relMSE, build/lvcl-compare).

    build/venv/bin/python bench/budget.py SCENE REFERENCE.exr --budgets 10,30
        [--modes lv,pt] [--width 256 --height 256] [--build build]
        [--lvcl-args "..."] [--out DIR] [--repeats 1] [--seed S] [--pass-spp 16]
        [--before OLD_BUILD --before-args "..."]

lvcl: `lvcl -q --time-limit T --mode M ...` per mode, no --spp unless given in
--lvcl-args.  "seconds" is what lvcl's --stats reports as spent under the
limit: for an lv render its budget's spent_seconds (particle passes,
pilot images and gather), else render_seconds plus particle_trace_seconds
(plus, for guided renders, the pilots that chose guided or plain paths);
"wall_seconds" is the whole process (startup, kernel build and writing the
image included).  Before the first budget each lvcl build renders every mode
once under a 2-second limit, image thrown away: a build whose kernels
changed would otherwise spend up to 3 s of its first budget on PoCL's
first-launch compiles (the program build is not counted, those are).  --before runs each of --modes with another build
(or the same build with other --before-args) as well, labelled lvcl-before (for error against time before and after a
change).

Mitsuba 3 (llvm_ad_rgb where it loads, else scalar_rgb; unidirectional path
tracer, max depth 64, Russian roulette from depth 5, as
tests/reference/render_reference.py): the glTF is converted and loaded once
("load_seconds", not counted).  Each run first renders one warm-up pass of
--pass-spp samples, which compiles the kernels on the first run and is
reported as "jit_seconds"; its samples are thrown away and its time is not
counted.  Then passes of --pass-spp samples, each with a re-seeded independent
sampler, are accumulated until the time spent is within half the last pass's
time of T (at least one pass), so it ends as near T as a pass allows.
"seconds" is the time of those passes, image readback included;
"total_seconds" adds the warm-up pass.

One JSON object per run goes to stdout, then a summary with, per budget, the
ratio relmse(lvcl mode) / relmse(mitsuba) for each lvcl mode, and with pt
among the modes relmse(mode) / relmse(lvcl pt) for the others (means over the
repeats).  Each repeat runs every renderer once, odd repeats in the reverse
order: machines whose speed drifts by 10-20% within minutes were seen, and
alternating cancels a steady drift.  A plot of relMSE against the seconds spent
goes to --out (default build/bench), with the images, when matplotlib is
available.
"""
import argparse
import json
import os
import shlex
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REFERENCE_TOOLS = os.path.join(HERE, "..", "tests", "reference")


def fail(message):
    """One line on stderr, exit status 1."""
    print(f"budget: {message}", file=sys.stderr)
    sys.exit(1)


def compare(build, image, reference):
    """lvcl-compare's JSON (relmse, rmse, mean, reference_mean)."""
    out = subprocess.run([os.path.join(build, "lvcl-compare"), image, reference],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def run_lvcl(a, mode, budget, seed, image, build=None, extra=None):
    """Renders SCENE with lvcl (of `build`, default --build) for `budget`
    seconds; returns its record."""
    stats = image + ".stats.json"
    cmd = [os.path.join(build or a.build, "lvcl"), "-q", "--width", str(a.width), "--height", str(a.height),
           "--seed", str(seed), "--time-limit", str(budget), "--stats", stats, "-o", image,
           "--mode", mode] + shlex.split(a.lvcl_args if extra is None else extra) + [a.scene]
    start = time.monotonic()
    subprocess.run(cmd, check=True)
    wall = time.monotonic() - start
    with open(stats) as f:
        s = json.load(f)
    keys = ("render_seconds", "particle_trace_seconds", "startup_seconds", "kernel_build_seconds",
            "spp", "samples", "samples_per_second", "particles", "particles_per_second", "grid")
    choice = s.get("guided_choice", {})
    seconds = (s["budget"]["spent_seconds"] if "budget" in s else
               s.get("render_seconds", 0.0) + s.get("particle_trace_seconds", 0.0) + choice.get("pilot_seconds", 0.0))
    rec = {"renderer": "lvcl" if build is None else "lvcl-before", "mode": mode, "seed": seed,
           "seconds": round(seconds, 4), "wall_seconds": round(wall, 4)}
    rec.update({k: s[k] for k in keys if k in s})
    if choice:
        rec["guided_choice"] = choice
    return rec


def load_mitsuba(a, workdir):
    """Converts and loads the scene; returns (mitsuba module, scene, variant, seconds)."""
    sys.path.insert(0, REFERENCE_TOOLS)
    import gltf_to_mitsuba as g2m
    import render_reference
    variant = render_reference.pick_variant(a.variant)
    import mitsuba as mi
    start = time.monotonic()
    d, _ = g2m.convert(a.scene, a.width, a.height, spp=a.pass_spp, workdir=workdir, max_depth=64, rr_depth=5)
    scene = mi.load_dict(d)
    return mi, scene, variant, time.monotonic() - start


def run_mitsuba(mi, scene, a, budget, seed, image):
    """Renders passes for `budget` seconds after a warm-up pass; returns its record."""
    import numpy as np
    from render_reference import write_exr

    def one_pass(k):
        img = mi.render(scene, spp=a.pass_spp, seed=seed * 1000003 + k)
        return np.array(img, dtype=np.float64)[:, :, :3]

    start = time.monotonic()
    one_pass(0)  # warm-up: kernel compilation on the first run; not counted
    jit = time.monotonic() - start
    acc, passes, last = 0.0, 0, 0.0
    t0 = time.monotonic()
    while passes == 0 or time.monotonic() - t0 + last / 2 <= budget:
        p0 = time.monotonic()
        acc = acc + one_pass(passes + 1)
        passes += 1
        last = time.monotonic() - p0
    seconds = time.monotonic() - t0
    write_exr(image, acc / passes)
    return {"renderer": "mitsuba", "mode": "pt", "seed": seed, "seconds": round(seconds, 4),
            "jit_seconds": round(jit, 4), "total_seconds": round(seconds + jit, 4),
            "spp": passes * a.pass_spp, "passes": passes, "pass_spp": a.pass_spp}


def summarize(records, modes):
    """Per budget: mean relMSE of each renderer/mode and lvcl's ratios to Mitsuba."""
    out = {}
    for budget in sorted({r["budget_seconds"] for r in records}):
        def mean(renderer, mode):
            v = [r["relmse"] for r in records
                 if r["budget_seconds"] == budget and r["renderer"] == renderer and r["mode"] == mode]
            return sum(v) / len(v) if v else None
        mit = mean("mitsuba", "pt")
        entry = {"relmse_mitsuba": mit}
        for m in modes:
            lv = mean("lvcl", m)
            entry[f"relmse_lvcl_{m}"] = lv
            entry[f"ratio_{m}_to_mitsuba"] = lv / mit if lv is not None and mit else None
        pt = entry.get("relmse_lvcl_pt")
        for m in modes:
            if m != "pt" and pt and entry[f"relmse_lvcl_{m}"] is not None:
                entry[f"ratio_{m}_to_lvcl_pt"] = entry[f"relmse_lvcl_{m}"] / pt
        out[str(budget)] = entry
    return out


def plot(records, path, title):
    """relMSE against the seconds spent on log-log axes, one line per renderer and mode."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("budget: matplotlib not found, no plot", file=sys.stderr)
        return
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for label in sorted({(r["renderer"], r["mode"]) for r in records}):
        pts = sorted((r["seconds"], r["relmse"]) for r in records if (r["renderer"], r["mode"]) == label)
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=" ".join(label))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("seconds spent")
    ax.set_ylabel("relMSE against the reference")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"budget: wrote {path}", file=sys.stderr)


def parse_args():
    """Command line; fails on a missing scene, reference, lvcl build or venv."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("reference")
    ap.add_argument("--budgets", default="10,30", help="seconds, comma separated (default 10,30)")
    ap.add_argument("--modes", default="lv,pt", help="lvcl modes, comma separated (default lv,pt)")
    ap.add_argument("--width", type=int, default=256)
    ap.add_argument("--height", type=int, default=256)
    ap.add_argument("--build", default="build")
    ap.add_argument("--lvcl-args", default="", help="extra lvcl arguments, one string")
    ap.add_argument("--out", default=os.path.join("build", "bench"))
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--seed", type=int, default=17)
    ap.add_argument("--pass-spp", type=int, default=16, help="Mitsuba samples per pass (default 16)")
    ap.add_argument("--variant", default=None, help="Mitsuba variant (default llvm_ad_rgb, else scalar_rgb)")
    ap.add_argument("--before", default=None,
                    help="another lvcl build (say, a worktree of an older commit) whose lv mode runs too, "
                         "labelled lvcl-before")
    ap.add_argument("--before-args", default="", help="its extra arguments, one string")
    a = ap.parse_args()
    a.budgets = [float(b) for b in a.budgets.split(",") if b]
    a.modes = [m for m in a.modes.split(",") if m]
    for path, what in ((a.scene, "scene"), (a.reference, "reference")):
        if not os.path.isfile(path):
            fail(f"{what} {path} not found")
    for tool in ("lvcl", "lvcl-compare"):
        if not os.access(os.path.join(a.build, tool), os.X_OK):
            fail(f"{os.path.join(a.build, tool)} not found; run `make`")
    try:
        import mitsuba  # noqa: F401
        import numpy  # noqa: F401
    except ImportError:
        fail("Mitsuba 3 is not importable here; run `make venv` and use build/venv/bin/python")
    return a


def main():
    a = parse_args()
    os.makedirs(a.out, exist_ok=True)
    compare(a.build, a.reference, a.reference)  # fails early if lvcl-compare cannot read it
    stem = os.path.splitext(os.path.basename(a.scene))[0]
    records = []
    with tempfile.TemporaryDirectory(prefix="lvcl_budget_") as workdir:
        mi, scene, variant, load = load_mitsuba(a, workdir)
        print(f"budget: Mitsuba {variant}, scene loaded in {load:.2f} s", file=sys.stderr)
        # Fill the kernel caches at the image size; these images are thrown away.
        warm = os.path.join(workdir, "warm.exr")
        for m in a.modes:
            run_lvcl(a, m, 2, a.seed, warm)
        for m in a.modes if a.before else []:
            run_lvcl(a, m, 2, a.seed, warm, a.before, a.before_args)
        for budget in a.budgets:
            for rep in range(a.repeats):
                seed = a.seed + rep
                runs = ([("lvcl", m) for m in a.modes] + [("lvcl-before", m) for m in a.modes if a.before] +
                        [("mitsuba", "pt")])
                # Odd repeats run in the reverse order, so that a machine whose
                # speed drifts during the benchmark favours no renderer on average.
                if rep % 2:
                    runs.reverse()
                for renderer, mode in runs:
                    image = os.path.join(a.out, f"budget_{stem}_{renderer}_{mode}_{budget:g}s_{rep}.exr")
                    if renderer == "lvcl":
                        rec = run_lvcl(a, mode, budget, seed, image)
                    elif renderer == "lvcl-before":
                        rec = run_lvcl(a, mode, budget, seed, image, a.before, a.before_args)
                    else:
                        rec = run_mitsuba(mi, scene, a, budget, seed, image)
                        rec.update({"variant": variant, "load_seconds": round(load, 4)})
                    e = compare(a.build, image, a.reference)
                    rec = {"scene": a.scene, "budget_seconds": budget, "repeat": rep, **rec,
                           "relmse": e["relmse"], "rmse": e["rmse"], "image": image}
                    records.append(rec)
                    print(json.dumps(rec), flush=True)
    print(json.dumps({"scene": a.scene, "summary": summarize(records, a.modes)}), flush=True)
    plot(records, os.path.join(a.out, f"budget_{stem}.png"), os.path.basename(a.scene))


if __name__ == "__main__":
    try:
        main()
    except subprocess.CalledProcessError as e:
        fail(f"{shlex.join(e.cmd)} exited with status {e.returncode}")
