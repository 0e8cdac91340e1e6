#!/usr/bin/env python3
"""The kitchen at scale (issue 5): load and BVH build time, peak host memory
and device memory of the smooth and the rippled kitchen, then the paper's
workload on each (a light volume of 5,000,000 particles, the gather at
49 spp, 640 x 480) and the ratio of rippled to smooth times (the paper saw
1.4x). Prints one JSON object per run, then a summary.

    bench/kitchen_scale.py [--build DIR] [--particles N] [--spp N]

Needs build/scenes/kitchen-rippled.glb (make kitchen-rippled).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile


def run(build, args, tmp):
    """Runs lvcl with --stats; returns the stats with the peak resident set
    size of the process (KiB, from wait4) and its wall time."""
    stats = os.path.join(tmp, "stats.json")
    cmd = [os.path.join(build, "lvcl"), "-q", "--stats", stats, "-o", os.path.join(tmp, "image.exr")] + args
    proc = subprocess.Popen(cmd)
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        sys.exit("kitchen_scale: %s failed with status %d" % (" ".join(cmd), proc.returncode))
    with open(stats) as f:
        s = json.load(f)
    s["peak_host_kib"] = usage.ru_maxrss
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--particles", default="5e6")
    ap.add_argument("--spp", default="49")
    a = ap.parse_args()
    scenes = {"smooth": "kitchen", "rippled": os.path.join(a.build, "scenes", "kitchen-rippled.glb")}
    if not os.path.exists(scenes["rippled"]):
        sys.exit("kitchen_scale: %s is missing (make kitchen-rippled)" % scenes["rippled"])
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for variant, scene in scenes.items():
            load = run(a.build, ["--mode", "pt", "--spp", "1", "--width", "64", scene], tmp)
            lv = run(a.build, ["--mode", "lv", "--particles", a.particles, "--spp", a.spp,
                               "--width", "640", "--height", "480", scene], tmp)
            rec = {
                "bench": "kitchen_scale", "variant": variant, "device": load["device"],
                "triangles": load["triangles"], "instances": load["instances"],
                "instanced_triangles": load["instanced_triangles"],
                "scene_load_seconds": load["scene_load_seconds"], "bvh_build_seconds": load["bvh_build_seconds"],
                "load_and_build_seconds": load["scene_load_seconds"] + load["bvh_build_seconds"],
                "peak_host_mib": load["peak_host_kib"] / 1024.0, "device_mib": load["device_bytes"] / 1048576.0,
                "lv_peak_host_mib": lv["peak_host_kib"] / 1024.0,
                "light_volume_mib": lv["light_volume_bytes"] / 1048576.0,
                "particles": lv["particles"], "particle_trace_seconds": lv["particle_trace_seconds"],
                "particles_per_second": lv["particles_per_second"], "segments_per_second": lv["segments_per_second"],
                "gather_spp": lv["spp"], "gather_seconds": lv["render_seconds"],
                "gather_samples_per_second": lv["samples_per_second"],
            }
            results[variant] = rec
            print(json.dumps(rec), flush=True)
    s, r = results["smooth"], results["rippled"]
    print(json.dumps({
        "bench": "kitchen_scale", "summary": True,
        "rippled_over_smooth_particle_trace": r["particle_trace_seconds"] / s["particle_trace_seconds"],
        "rippled_over_smooth_gather": r["gather_seconds"] / s["gather_seconds"],
        "rippled_over_smooth_total": (r["particle_trace_seconds"] + r["gather_seconds"]) /
                                     (s["particle_trace_seconds"] + s["gather_seconds"]),
    }))


if __name__ == "__main__":
    main()
