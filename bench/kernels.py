#!/usr/bin/env python3
"""Kernel microbenchmarks on every OpenCL device: traversal (the primary,
diffuse and shadow workloads of lvcl-bench rays), the particle trace, the
subcell visibility rays (by difference: the same trace with --subcells 0),
the gather and the path tracer, as throughput and time. On PoCL's pthread
device each runs with 1 and with 2 threads (POCL_MAX_PTHREAD_COUNT), and
the summary gives the 2-thread speed-up. Prints one JSON object per run.

    bench/kernels.py [--build DIR] [--scene SCENE] [--particles N] [--spp N]

PoCL's devices are all exposed (POCL_DEVICES="pthread basic") unless
POCL_DEVICES is already set.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile


def devices(build, env):
    out = subprocess.run([os.path.join(build, "lvcl"), "--list-devices"], env=env, check=True,
                         capture_output=True, text=True).stdout
    found = []
    for line in out.splitlines():
        m = re.match(r"\s*(\d+)\s+(\S+)\s+(\S+)", line)
        if m:
            found.append((int(m.group(1)), m.group(3)))
    return found


def lvcl_stats(build, env, args, tmp):
    stats = os.path.join(tmp, "stats.json")
    subprocess.run([os.path.join(build, "lvcl"), "-q", "--stats", stats, "-o", os.path.join(tmp, "x.exr")] + args,
                   env=env, check=True)
    with open(stats) as f:
        return json.load(f)


def rays(build, env, device, scene):
    out = subprocess.run([os.path.join(build, "lvcl-bench"), "rays", "--device", str(device), "--width", "1024",
                          "--repeat", "5", scene], env=env, check=True, capture_output=True, text=True).stdout
    result = {}
    for line in out.splitlines():
        r = json.loads(line)
        if "workload" in r:
            result[r["workload"]] = {"mrays_per_second": r["mrays"], "seconds": r.get("seconds")}
    return result


def measure(build, env, device, a, tmp):
    common = ["--device", str(device), "--width", "256", "--seed", "3", a.scene]
    lv = lvcl_stats(build, env, ["--mode", "lv", "--particles", a.particles, "--spp", a.spp] + common, tmp)
    whole = lvcl_stats(build, env, ["--mode", "lv", "--subcells", "0", "--particles", a.particles, "--spp", a.spp]
                       + common, tmp)
    pt = lvcl_stats(build, env, ["--mode", "pt", "--spp", a.spp] + common, tmp)
    vis_seconds = lv["particle_trace_seconds"] - whole["particle_trace_seconds"]
    return {
        "traversal": rays(build, env, device, a.scene),
        "particle_trace": {"seconds": lv["particle_trace_seconds"], "particles_per_second": lv["particles_per_second"],
                           "segments_per_second": lv["segments_per_second"]},
        "subcell_visibility": {"rays": lv["visibility_rays"], "seconds": vis_seconds,
                               "rays_per_second": lv["visibility_rays"] / vis_seconds if vis_seconds > 0 else None},
        "gather": {"seconds": lv["render_seconds"], "samples_per_second": lv["samples_per_second"]},
        "path_tracer": {"seconds": pt["render_seconds"], "samples_per_second": pt["samples_per_second"]},
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--scene", default="cornell")
    ap.add_argument("--particles", default="500000")
    ap.add_argument("--spp", default="16")
    a = ap.parse_args()
    env = dict(os.environ)
    env.setdefault("POCL_DEVICES", "pthread basic")
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        for index, name in devices(a.build, env):
            threads = [1, 2] if name.startswith("pthread") else [None]
            for t in threads:
                e = dict(env)
                if t:
                    e["POCL_MAX_PTHREAD_COUNT"] = str(t)
                rec = {"bench": "kernels", "device": name, "device_index": index, "threads": t, "scene": a.scene}
                rec.update(measure(a.build, e, index, a, tmp))
                runs.append(rec)
                print(json.dumps(rec), flush=True)
    for name in {r["device"] for r in runs if r["threads"]}:
        one = next(r for r in runs if r["device"] == name and r["threads"] == 1)
        two = next(r for r in runs if r["device"] == name and r["threads"] == 2)
        speedup = {w: two["traversal"][w]["mrays_per_second"] / one["traversal"][w]["mrays_per_second"]
                   for w in one["traversal"]}
        for k in ("particle_trace", "gather", "path_tracer"):
            speedup[k] = one[k]["seconds"] / two[k]["seconds"]
        print(json.dumps({"bench": "kernels", "summary": True, "device": name, "speedup_2_threads_over_1": speedup}))


if __name__ == "__main__":
    sys.exit(main())
