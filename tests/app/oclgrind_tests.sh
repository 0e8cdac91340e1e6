#!/bin/sh
# Every kernel of every pass under Oclgrind, the simulator that checks each
# memory access: lvcl and lvcl-bench run tiny scenes on the Oclgrind device
# (the build's opencl-vendors lists it) with its API, bounds and data-race
# checks on. A run passes when it exits 0, Oclgrind reports nothing, and
# its image is device 0's (one seed, the same random numbers).
build=${1:-build}
lvcl="$build/lvcl"
scenes=$(dirname "$0")/../../scenes
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

pass() { echo "PASS $1"; }
fail() { echo "FAIL $1: $2"; }

device=$("$lvcl" --list-devices 2>/dev/null | awk '/\(simulator/ && /Oclgrind/ { print $1; exit }')
if [ -z "$device" ]; then
    echo "SKIP oclgrind: no Oclgrind device (make installs Debian's oclgrind and lists it in $build/opencl-vendors)"
    exit 0
fi
export OCLGRIND_CHECK_API=1 OCLGRIND_DATA_RACES=1

# Oclgrind prints each problem it finds on stderr; lvcl -q prints nothing
# on success. clean NAME: the run's status and stderr say nothing is wrong.
clean() {
    if [ "$status" -ne 0 ] || [ -s "$tmp/err" ]; then
        fail "$1" "exit status $status; $(grep -v '^\s*$' "$tmp/err" | head -8 | tr '\n' ' ')"
        return 1
    fi
}

# render NAME TOLERANCE ARGS...: the run under Oclgrind is clean and its
# image matches device 0's within relMSE TOLERANCE: 1e-6 on the Cornell
# box (measured up to 3e-12), 1e-5 on the kitchen (measured 1e-7 to 2e-6:
# float rounding differs between the two compilers), against noise of
# about 1e-1 at 1 spp. The kitchen's light volume 3e-5: its particles'
# rounding moves the volume's bins by a percent here and there (6.8e-6
# on a 2-core Intel Xeon, AVX-512), and since 2026-12-07 its glossy tiles'
# near hits go on as paths that read the volume at more points (1.1e-5).
render() {
    name=$1 tolerance=$2
    shift 2
    "$lvcl" -q --seed 3 --width 8 --height 8 --spp 1 --device "$device" -o "$tmp/sim.exr" "$@" 2>"$tmp/err"
    status=$?
    clean "Oclgrind: $name" || return
    "$lvcl" -q --seed 3 --width 8 --height 8 --spp 1 --device 0 -o "$tmp/ref.exr" "$@" 2>"$tmp/err0"
    e=$("$build/lvcl-compare" "$tmp/sim.exr" "$tmp/ref.exr" 2>&1 | sed -n 's/.*"relmse": \([^,]*\),.*/\1/p')
    if [ -n "$e" ] && awk -v e="$e" -v t="$tolerance" 'BEGIN { exit !(e <= t) }'; then
        pass "Oclgrind: $name (relMSE $e against device 0)"
    else
        fail "Oclgrind: $name" "relMSE ${e:-unknown} against device 0 (tolerance $tolerance); $(cat "$tmp/err0")"
    fi
}

# "scene tables split": a device of a few hundred KiB (--device-memory)
# holds the kitchen only in several buffers per table.
lv="--mode lv --cells 6 --particles 1500"
render "path tracer" 1e-6 --mode pt cornell
render "path tracer, glass and textures" 1e-6 --mode pt --max-depth 4 "$scenes/glass-table.gltf"
render "light volume (trace, visibility rays, gather)" 1e-6 $lv cornell
render "light volume, lights' own segments (lv-all)" 1e-6 --mode lv-all --cells 6 --particles 1500 cornell
render "light volume, sampled gather" 1e-6 $lv --gather sample cornell
render "light volume, refined cells and directions" 1e-6 $lv --refine 1 --refine-dirs 2 cornell
render "light volume, adaptive cells" 3e-5 $lv --merge-tolerance 0.25 --subcells 2 kitchen
render "light volume, lamps seen through glass" 1e-5 $lv "$scenes/glass-table.gltf"
render "guided path tracer" 1e-6 --mode guided --cells 6 --particles 1500 cornell
render "scene tables split over buffers" 1e-5 --mode pt --device-memory 0.3 kitchen
render "adaptive sampling" 1e-6 --mode pt --spp 16 --adaptive on --width 4 cornell
export LVCL_EMULATE_INT64_ATOMICS=1
render "64-bit tallies from 32-bit atomics" 1e-6 $lv --stats "$tmp/stats.json" cornell
unset LVCL_EMULATE_INT64_ATOMICS
if grep -q '"kernel_options".*-DLV_EMULATE_INT64_ATOMICS' "$tmp/stats.json"; then pass "Oclgrind: the 32-bit-atomics run built that path"
else fail "Oclgrind: the 32-bit-atomics run built that path" "$(grep kernel_options "$tmp/stats.json")"; fi

# The benchmarks' kernels: rays of every workload, and the wavefront path
# tracer's stages.
# Oclgrind cannot run the intrinsic LLVM's inliner leaves in the ray
# kernels (llvm.experimental.noalias.scope.decl, Oclgrind issue 223), so
# they are built unoptimised, with a cache of their own.
LVCL_CACHE_DIR="$tmp/cache" OCLGRIND_BUILD_OPTIONS=-cl-opt-disable \
    "$build/lvcl-bench" rays --device "$device" --width 8 --repeat 1 cornell >"$tmp/rays.json" 2>"$tmp/err"
status=$?
clean "Oclgrind: lvcl-bench rays" && pass "Oclgrind: lvcl-bench rays"
"$build/lvcl-bench" wavefront --device "$device" --width 8 --spp 1 cornell >"$tmp/wf.json" 2>"$tmp/err"
status=$?
clean "Oclgrind: lvcl-bench wavefront" && pass "Oclgrind: lvcl-bench wavefront"
