#!/bin/sh
# A short, bounded fuzz of the glTF importer and of the command line (make
# fuzz runs longer): each libFuzzer harness replays its regression files in
# tests/data/fuzz/<harness>/, then mutates a corpus seeded with the
# embedded and test scenes for FUZZ_TEST_SECONDS (default 15). A crash, a
# sanitizer report or a message that is not one line fails. The corpus and
# any crashing input are kept in FUZZ_WORK_DIR if set (make fuzz: the
# build tree), else in a temporary folder.
build=${1:-build}
here=$(dirname "$0")
seconds=${FUZZ_TEST_SECONDS:-15}
if [ -n "$FUZZ_WORK_DIR" ]; then
    tmp=$FUZZ_WORK_DIR
    mkdir -p "$tmp"
else
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
fi

for name in fuzz_gltf fuzz_options; do
    fuzzer="$build/fuzz/$name"
    if [ ! -x "$fuzzer" ]; then
        echo "FAIL $name: $fuzzer is not built (make builds it with Debian's clang)"
        continue
    fi
    corpus="$tmp/corpus-$name"
    mkdir -p "$corpus"
    [ "$name" = fuzz_gltf ] && cp "$here"/../../scenes/*.gltf "$here"/../data/gltf/*.gltf "$here"/../data/gltf/*.glb "$here"/../data/gltf/corners/*.gltf "$here"/../data/gltf/corners/*.glb "$corpus"/
    regressions="$here/../data/fuzz/$name"
    if [ -d "$regressions" ]; then
        if "$fuzzer" "$regressions"/* >"$tmp/log" 2>&1; then echo "PASS $name: $(ls "$regressions" | wc -l) regression files"
        else echo "FAIL $name: a regression file fails: $(grep -m2 -E 'ERROR|SUMMARY|refused' "$tmp/log")"; fi
    fi
    if "$fuzzer" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 -print_final_stats=1 \
        -artifact_prefix="$tmp/" "$corpus" >"$tmp/log" 2>&1; then
        runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$tmp/log")
        cov=$(grep -E '^#[0-9]+' "$tmp/log" | tail -1 | sed -n 's/.*cov: \([0-9]*\).*/\1/p')
        echo "PASS $name: $runs runs in $seconds s, no crash (coverage: $cov edges)"
    else
        echo "FAIL $name: $(grep -m3 -E 'ERROR|SUMMARY|refused' "$tmp/log" | tr '\n' ' ') (input saved as $(ls "$tmp" | grep -m1 -E '^(crash|leak|timeout|oom)-'))"
    fi
done
