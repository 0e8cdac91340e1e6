#!/bin/sh
# Builds what a borrowed GPU machine needs to run lvcl's kernels and tests
# (docs/devices.md, "On a GPU"): lvcl, lvcl-bench and every test program
# with image files as PFM instead of OpenImageIO, the OpenCL ICD loader and
# tinygltf's libraries, the references as PFM and the 1M-triangle room, in
# build/device-check (about 45 MB). Run from the repository root after make.
#   bench/device_check/bundle.sh [BUILD]
set -e
build=${1:-build}
out=$build/device-check
here=bench/device_check
[ -e "$build/liblvcl.a" ] || { echo "bundle.sh: error: no $build/liblvcl.a; run make first" >&2; exit 1; }
rm -rf "$out" && mkdir -p "$out/bin/tests" "$out/lib" "$out/ref" "$out/obj"
cflags="-std=c11 -D_POSIX_C_SOURCE=200809L -O2"
libs="-lOpenCL -ltinygltf -lstdc++ -lm -lpthread"

cc $cflags -o "$out/obj/to_pfm" $here/to_pfm.c "$build/liblvcl.a" -lOpenImageIO -lOpenImageIO_Util $libs
for f in tests/reference/*.exr; do "$out/obj/to_pfm" "$f" "$out/ref/$(basename "$f" .exr).pfm"; done

lib="$out/obj/liblvcl-pfm.a"
cp "$build/liblvcl.a" "$lib" && ar d "$lib" image_io.o
cc $cflags -c -o "$out/obj/image_io_pfm.o" $here/image_io_pfm.c && ar r "$lib" "$out/obj/image_io_pfm.o"
cc $cflags -o "$out/bin/lvcl" host/app/main.c "$lib" $libs
cc $cflags -o "$out/bin/lvcl-bench" bench/main.c bench/common.c bench/rays.c bench/wavefront.c \
    "$build/gen/bench_kernel_source.c" "$build/gen/wavefront_kernel_source.c" "$lib" $libs
for t in tests/*/test_*.c; do
    support=$(ls "$(dirname "$t")"/*.c | grep -v /test_ || true)
    cc $cflags -o "$out/bin/tests/$(basename "$t" .c)" "$t" $support tests/harness.c \
        "$build/gen/test_kernel_source.c" "$lib" $libs
done
strip "$out"/bin/lvcl* "$out"/bin/tests/*
# The libraries the GPU machine may lack (its own C and C++ runtimes serve).
for l in libOpenCL.so.1 libtinygltf.so libstb.so.0; do
    cp -L "$(ldconfig -p | grep -F "$l" | head -1 | awk '{print $NF}')" "$out/lib/"
done
python3 bench/make_big_scene.py "$out/big_room.glb" >/dev/null
rm -rf "$out/obj"
du -sh "$out"
