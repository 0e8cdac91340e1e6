#!/bin/sh
# Error against a reference as the sample count grows: one JSON object per
# run, with the render's wall time and its relMSE and RMSE.
#   bench/convergence.sh [--build DIR] SCENE REFERENCE.exr SPP...
# Example: bench/convergence.sh scenes/cornell.gltf tests/reference/cornell.exr 16 64 256 1024
build=build
if [ "$1" = "--build" ]; then build=$2; shift 2; fi
if [ $# -lt 3 ]; then
    echo "usage: $0 [--build DIR] SCENE REFERENCE.exr SPP..." >&2
    exit 2
fi
scene=$1 ref=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for spp in "$@"; do
    "$build/lvcl" -q --mode pt --spp "$spp" --width 256 --height 256 --seed 11 -o "$tmp/img.exr" --stats "$tmp/stats.json" "$scene" ||
        exit 1
    seconds=$(sed -n 's/.*"render_seconds": \([0-9.]*\).*/\1/p' "$tmp/stats.json")
    err=$("$build/lvcl-compare" "$tmp/img.exr" "$ref")
    relmse=$(echo "$err" | sed -n 's/.*"relmse": \([^,]*\),.*/\1/p')
    rmse=$(echo "$err" | sed -n 's/.*"rmse": \([^,]*\),.*/\1/p')
    echo "{\"scene\": \"$scene\", \"mode\": \"pt\", \"spp\": $spp, \"render_seconds\": $seconds, \"relmse\": $relmse, \"rmse\": $rmse}"
done
