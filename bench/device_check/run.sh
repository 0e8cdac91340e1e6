#!/bin/bash
# Runs on the GPU machine from the repository root, with build/device-check
# carried there (bundle.sh): lvcl's kernels on the vendor's OpenCL, the
# renders and benchmarks of docs/devices.md and every test program with
# LVCL_TEST_DEVICE=gpu. Writes log.txt, rays.jsonl and renders.tar (images as
# PFM, --stats JSON) to $OUT (default: out/device-check).
#   bench/device_check/run.sh [SECONDS_FOR_TESTS]
out=${OUT:-out/device-check}
mkdir -p "$out"
exec > >(tee "$out/log.txt") 2>&1
start=$(date +%s)
stage() { echo "== [$(($(date +%s) - start)) s] $*"; }
bundle=$PWD/build/device-check
export LD_LIBRARY_PATH=$bundle/lib LVCL_PFM_DIR=$bundle/ref LVCL_CACHE_DIR=/tmp/lvcl-cache LVCL_TEST_DEVICE=gpu
# The driver's OpenCL library, wherever the machine mounts it, as the only ICD.
icd=""
for d in /usr/local/nvidia/lib64 /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/local/cuda/lib64; do
    icd=$(ls $d/libnvidia-opencl.so* $d/libamdocl64.so* 2>/dev/null | head -1)
    [ -n "$icd" ] && break
done
[ -n "$icd" ] || { stage "no vendor OpenCL library found"; exit 1; }
mkdir -p /tmp/lvcl-vendors && echo "$icd" >/tmp/lvcl-vendors/gpu.icd
export OCL_ICD_VENDORS=/tmp/lvcl-vendors
nvidia-smi -L 2>/dev/null
"$bundle/bin/lvcl" --list-devices || exit 1

renders=/tmp/lvcl-renders
mkdir -p $renders
render() { # NAME, then lvcl's arguments
    local name=$1
    shift
    stage "lvcl $name: $*"
    timeout 120 "$bundle/bin/lvcl" -q --device gpu --stats $renders/$name.json -o $renders/$name.pfm "$@"
    grep -E '"(kernel_build|render|particle_trace)_seconds"|checksum' $renders/$name.json | tr -d '\n '
    echo
}
render cornell_lv --mode lv --width 256 --height 256 --spp 16 --seed 4 cornell
render cornell_pt --mode pt --width 256 --height 256 --spp 1024 --seed 4 cornell
render glass_pt --mode pt --width 256 --height 256 --spp 256 --seed 4 scenes/glass-table.gltf
render glass_guided --mode guided --width 256 --height 256 --spp 256 --seed 4 scenes/glass-table.gltf
render kitchen_pt --mode pt --width 160 --height 120 --spp 256 --seed 4 kitchen
render kitchen_lv5m --mode lv --particles 5e6 --width 160 --height 120 --spp 64 --seed 4 kitchen
render cornell_lv_10s --mode lv --width 256 --height 256 --time-limit 10 --spp 1000000 cornell
tar cf "$out/renders.tar" -C $renders .
for scene in cornell kitchen "$bundle/big_room.glb"; do
    stage "rays $scene"
    timeout 120 "$bundle/bin/lvcl-bench" rays --device gpu --repeat 3 "$scene" | tee -a "$out/rays.jsonl"
done
stage "wavefront against the megakernel"
timeout 60 "$bundle/bin/lvcl-bench" wavefront --device gpu --spp 1024 cornell
timeout 60 "$bundle/bin/lvcl-bench" wavefront --device gpu --spp 256 kitchen

tests_start=$(date +%s)
for t in "$bundle"/bin/tests/test_*; do
    [ $(($(date +%s) - tests_start)) -gt "${1:-300}" ] && { stage "out of time before $(basename "$t")"; continue; }
    stage "$(basename "$t")"
    timeout 90 "$t" tests >/tmp/lvcl-test.log 2>&1
    status=$?
    grep -E '^(FAIL|SKIP)' /tmp/lvcl-test.log
    passed=$(grep -c ^PASS /tmp/lvcl-test.log)
    failed=$(grep -c ^FAIL /tmp/lvcl-test.log)
    echo "-- $(basename "$t"): $passed passed, $failed failed, exit $status"
done
stage done
