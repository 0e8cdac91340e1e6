#!/usr/bin/env python3
"""lvcl-mpi's scaling: one lv render per rank count, particle count and grid,
each rank's compute and communication per phase from lvcl's --stats.

    python3 bench/mpi_scaling.py [SCENE] [--ranks 1,2,3] [--particles 1e6,1e7]
        [--cells 32,64] [--spp 4] [--width 160] [--build build]

Runs `mpirun --oversubscribe --bind-to none -np N build/lvcl-mpi -q --mode lv
--adaptive off ...` (SCENE defaults to the embedded kitchen, the paper's
workload) and prints one JSON object per run, then a summary object:

- "wall_seconds": the whole mpirun, start-up and image writing included;
- per rank: "particle_trace_seconds" (its devices tracing), "render_seconds"
  (its devices gathering), "comm_seconds" and "comm_bytes" per phase
  ("particles": taking batches, agreeing and adding the volumes; "image":
  taking bands, agreeing and adding the image; "setup": agreeing on the
  scene and devices);
- "volume_bytes": the tallies and subcell records one reduction adds
  (lvcl's light_volume_bytes on the device, an upper bound);
- "volume_reduce_seconds": the slowest rank's time adding the volumes
  (MPI_Allreduce of the tallies and records), the model's reduction term;
- "comm_share": the particle phase's communication over the slowest rank's
  trace plus that communication, the fraction docs/distributed.md's model
  uses.

On one machine the ranks share its cores, so more ranks are not faster; the
figures give the model its inputs (docs/distributed.md, "Scaling").
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time


def fail(message):
    print(f"mpi_scaling: {message}", file=sys.stderr)
    sys.exit(1)


def numbers(text, kind):
    try:
        return [kind(float(x)) for x in text.split(",") if x]
    except ValueError:
        fail(f"expected a comma-separated list of numbers, not '{text}'")


def run(args, ranks, particles, cells, scratch):
    stats = os.path.join(scratch, "stats.json")
    command = ["mpirun", "--oversubscribe", "--bind-to", "none", "-q", "-np", str(ranks),
               os.path.join(args.build, "lvcl-mpi"), "-q", "--mode", "lv", "--adaptive", "off",
               "--particles", str(particles), "--cells", str(cells), "--spp", str(args.spp),
               "--width", str(args.width), "-o", os.path.join(scratch, "image.exr"), "--stats", stats,
               args.scene]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    start = time.monotonic()
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    wall = time.monotonic() - start
    if done.returncode != 0:
        fail(f"{' '.join(command)} failed ({done.returncode}): {done.stderr.strip()[-400:]}")
    with open(stats) as f:
        s = json.load(f)
    rank_list = s.get("ranks") or [{
        "rank": 0, "particles": s["particles"], "particle_trace_seconds": s["particle_trace_seconds"],
        "render_busy_seconds": s["render_seconds"],
        "comm_seconds": {"setup": 0, "particles": 0, "image": 0},
        "reduce_seconds": {"particles": 0, "image": 0},
        "comm_bytes": {"setup": 0, "particles": 0, "image": 0}}]
    slowest = max(r["particle_trace_seconds"] for r in rank_list)
    comm = max(r["comm_seconds"]["particles"] for r in rank_list)
    reduce = max(r["reduce_seconds"]["particles"] for r in rank_list)
    return {
        "scene": args.scene, "ranks": ranks, "particles": particles, "cells": cells,
        "grid": s["grid"], "volume_bytes": s["light_volume_bytes"],
        "light_volume_checksum": s["light_volume_checksum"],
        "wall_seconds": round(wall, 3),
        "particle_phase_seconds": round(slowest + comm, 4),
        "comm_share": round(comm / (slowest + comm), 4) if slowest + comm > 0 else 0,
        "volume_reduce_seconds": round(reduce, 4),
        "per_rank": [{
            "rank": r["rank"], "particles": r["particles"],
            "particle_trace_seconds": r["particle_trace_seconds"],
            "render_seconds": r["render_busy_seconds"],
            "comm_seconds": r["comm_seconds"], "reduce_seconds": r.get("reduce_seconds"),
            "comm_bytes": r["comm_bytes"]} for r in rank_list],
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("scene", nargs="?", default="kitchen")
    p.add_argument("--ranks", default="1,2,3")
    p.add_argument("--particles", default="1e6,1e7")
    p.add_argument("--cells", default="32,64")
    p.add_argument("--spp", type=int, default=4)
    p.add_argument("--width", type=int, default=160)
    p.add_argument("--build", default="build")
    args = p.parse_args()
    if not os.access(os.path.join(args.build, "lvcl-mpi"), os.X_OK):
        fail(f"no {args.build}/lvcl-mpi (make builds it)")
    results = []
    with tempfile.TemporaryDirectory() as scratch:
        for particles in numbers(args.particles, int):
            for cells in numbers(args.cells, int):
                for ranks in numbers(args.ranks, int):
                    r = run(args, ranks, particles, cells, scratch)
                    print(json.dumps(r), flush=True)
                    results.append(r)
    # The volumes of one particle count and grid must be the same on every rank count.
    same = {}
    for r in results:
        same.setdefault((r["particles"], r["cells"]), set()).add(r["light_volume_checksum"])
    print(json.dumps({"summary": [
        {"particles": r["particles"], "cells": r["cells"], "ranks": r["ranks"],
         "volume_bytes": r["volume_bytes"], "comm_share": r["comm_share"],
         "volume_reduce_seconds": r["volume_reduce_seconds"],
         "particle_phase_seconds": r["particle_phase_seconds"], "wall_seconds": r["wall_seconds"]}
        for r in results],
        "volumes_equal_across_ranks": all(len(v) == 1 for v in same.values())}))


if __name__ == "__main__":
    main()
