#!/bin/sh
# lvcl-mpi (docs/distributed.md): one frame over 1, 2 and 3 MPI ranks on
# this machine (oversubscribed) must give the single-process image and
# light volume bit for bit, in every mode and with every kind of volume;
# bad input is reported once; a rank that fails or dies ends the job.
build=${1:-build}
lvcl="$build/lvcl"
mpi="$build/lvcl-mpi"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

pass() { echo "PASS $1"; }
fail() { echo "FAIL $1: $2"; }

if ! command -v mpirun >/dev/null; then
    fail "mpirun" "not found (make installs Debian's openmpi-bin)"
    exit 1
fi
if [ ! -x "$mpi" ]; then
    fail "lvcl-mpi" "$mpi was not built"
    exit 1
fi
# Open MPI refuses root unless told; CI runs as root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# More ranks than cores, and no binding: two cores hold three ranks.
run_mpi() { # N ARGS...: lvcl-mpi on N ranks
    n=$1
    shift
    mpirun --oversubscribe --bind-to none -q -np "$n" "$mpi" "$@"
}

# same NAME A.exr B.exr: the images are equal bit for bit (RMSE exactly 0).
same() {
    if "$build/lvcl-compare" "$2" "$3" 2>&1 | grep -q '"rmse": 0,'; then pass "$1"
    else fail "$1" "$("$build/lvcl-compare" "$2" "$3" 2>&1)"; fi
}

# field FILE KEY: a top-level field of a stats file.
field() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1])).get(sys.argv[2]))' "$1" "$2"; }

# compare_runs NAME ARGS...: lvcl and lvcl-mpi on each of $ranks ranks,
# same image; same light volume where there is one.
ranks="1 2 3"
compare_runs() {
    name=$1
    shift
    if ! "$lvcl" -q "$@" -o "$tmp/one.exr" --stats "$tmp/one.json" 2>"$tmp/err"; then
        fail "$name: single process" "$(head -3 "$tmp/err")"
        return
    fi
    for n in $ranks; do
        if ! run_mpi "$n" -q "$@" -o "$tmp/mpi$n.exr" --stats "$tmp/mpi$n.json" 2>"$tmp/err"; then
            fail "$name, $n ranks" "$(head -3 "$tmp/err")"
            continue
        fi
        same "$name, $n ranks: the single-process image" "$tmp/one.exr" "$tmp/mpi$n.exr"
        want=$(field "$tmp/one.json" light_volume_checksum)
        got=$(field "$tmp/mpi$n.json" light_volume_checksum)
        [ "$want" = None ] && continue
        if [ "$want" = "$got" ]; then pass "$name, $n ranks: the single-process light volume"
        else fail "$name, $n ranks: the single-process light volume" "checksum $got, expected $want"; fi
    done
}

# Particles are handed out in batches of 2^18: 7 x 10^5 makes three, so
# ranks share the trace. Past 8 spp adaptive sampling (on by default)
# plans its epochs from every rank's bands.
small="--width 80 --spp 20 cornell"
compare_runs "pt, adaptive" --mode pt $small
compare_runs "lv" --mode lv --particles 7e5 $small
ranks="1 3"
compare_runs "lv-all" --mode lv-all --particles 7e5 $small
compare_runs "guided" --mode guided --particles 7e5 $small
# The variants on 3 ranks, where every rank takes work.
ranks=3
compare_runs "pt, uniform" --mode pt --adaptive off --spp 6 --width 80 cornell
# Sampling gather, no subcells, an offset grid of another size.
compare_runs "lv, sampled gather, no subcells, 20 offset cells" --mode lv --gather sample --subcells 0 --cells 20 \
    --grid-offset 0.37 --particles 7e5 $small
# Refined cells and directions: the split after a quarter of the
# particles is decided on every rank from the summed tallies, and only
# rank 0's first device keeps the first part.
compare_runs "lv, refined cells and directions" --mode lv --refine 1 --refine-dirs on --particles 1.2e6 $small
compare_runs "lv, merged cells" --mode lv --merge-tolerance 0.5 --particles 7e5 $small
# Instances, glass and textures.
compare_runs "kitchen lv" --mode lv --particles 6e5 --width 48 --spp 10 kitchen
# Two devices a rank (PoCL's pthread and basic): bands and batches over
# four devices; uniform sampling, as on two devices alone.
(export POCL_DEVICES="pthread basic"
 compare_runs "two devices a rank, lv" --device 0,1 --mode lv --particles 7e5 $small)

# The stats list each rank's share; the shares add up to the whole.
run_mpi 3 -q --mode lv --adaptive off --particles 7e5 --width 80 --spp 4 --stats "$tmp/ranks.json" \
    -o "$tmp/ranks.exr" cornell 2>"$tmp/err"
if python3 - "$tmp/ranks.json" <<'EOF'; then pass "stats: each rank's share and communication"
import json, sys
s = json.load(open(sys.argv[1]))
r = s["ranks"]
assert len(r) == 3, r
assert sum(k["particles"] for k in r) == s["particles"] == 700000, (s["particles"], r)
assert sum(k["pixels"] for k in r) == s["width"] * s["height"], r
for k in r:
    assert k["comm_bytes"]["particles"] > 0 and k["comm_seconds"]["image"] >= 0, k
EOF
else fail "stats: each rank's share and communication" "$(cat "$tmp/ranks.json" "$tmp/err" | tail -20)"; fi

# Progress and messages come from rank 0 only.
run_mpi 3 --spp 2 --width 32 -o "$tmp/talk.exr" cornell 2>"$tmp/err"
if [ "$(grep -c 's in all' "$tmp/err")" -eq 1 ] && grep -q 'over 3 ranks' "$tmp/err"; then
    pass "one closing line, from rank 0"
else fail "one closing line, from rank 0" "$(cat "$tmp/err")"; fi

# expect_error NAME STATUS PATTERN MPIRUN-ARGS...: exactly one lvcl error
# line, matching PATTERN, and the status.
expect_error() {
    name=$1 want=$2 pattern=$3
    shift 3
    mpirun --oversubscribe --bind-to none -q "$@" >"$tmp/out" 2>"$tmp/err"
    status=$?
    lines=$(grep -c '^lvcl: error: ' "$tmp/err")
    if [ "$status" -ne "$want" ]; then fail "$name" "status $status, expected $want: $(head -5 "$tmp/err")"
    elif [ "$lines" -ne 1 ] || ! grep -Eq "$pattern" "$tmp/err"; then
        fail "$name" "expected one error line matching /$pattern/: $(head -8 "$tmp/err")"
    else pass "$name"; fi
}
expect_error "bad flag, reported once" 2 "unknown option" -np 3 "$mpi" --frobnicate cornell
expect_error "missing scene, reported once" 1 "no-such.gltf" -np 3 "$mpi" "$tmp/no-such.gltf"
expect_error "time limit over ranks refused" 2 "one process only" -np 2 "$mpi" --time-limit 5 cornell
expect_error "a device that fails on one rank names it" 1 "rank 1: device 99 does not exist" \
    -np 1 "$mpi" --mode pt --spp 1 --width 8 cornell : -np 1 "$mpi" --mode pt --device 99 --spp 1 --width 8 cornell
expect_error "a device that fails on one of three names it" 1 "rank 2: device 99" \
    -np 2 "$mpi" --mode pt --spp 1 --width 8 cornell : -np 1 "$mpi" --mode pt --device 99 --spp 1 --width 8 cornell

# A rank killed during the particle trace ends the job, non-zero, within
# 30 s, and mpirun names the rank.
mpirun --oversubscribe --bind-to none -np 3 "$mpi" -q --mode lv --particles 4e9 --width 32 cornell \
    >"$tmp/out" 2>"$tmp/err" &
job=$!
victim=""
for _ in $(seq 1 100); do
    for p in $(pgrep -f "$mpi" 2>/dev/null); do
        tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1' && victim=$p
    done
    [ -n "$victim" ] && break
    sleep 0.2
done
sleep 4 # into the trace (the kernels are cached by the runs above)
start=$(date +%s)
[ -n "$victim" ] && kill -9 "$victim"
( sleep 30; kill -9 "$job" 2>/dev/null ) &
watchdog=$!
wait "$job"
status=$?
kill "$watchdog" 2>/dev/null
took=$(($(date +%s) - start))
if [ -z "$victim" ]; then fail "a killed rank ends the job" "rank 1 was not found"
elif [ "$status" -eq 0 ] || [ "$took" -ge 30 ]; then fail "a killed rank ends the job" "status $status after $took s"
elif ! grep -q "rank 1" "$tmp/err"; then fail "a killed rank ends the job" "no rank named: $(head -8 "$tmp/err")"
else pass "a killed rank ends the job (status $status in $took s, rank named)"; fi

# SIGUSR2 to mpirun, which forwards it to every rank, stops sampling and
# keeps the image so far (mpirun ends the job on SIGINT or SIGTERM): after
# the adaptive epoch it came in, or, during the particle trace, at the next
# batch and then after one epoch. Status 128 + 12.
stop_with_usr2() { # NAME SECONDS LVCL-MPI-ARGS...
    name=$1 wait_s=$2
    shift 2
    rm -f "$tmp/usr2.exr" "$tmp/usr2.json"
    mpirun --oversubscribe --bind-to none -np 2 "$mpi" -q "$@" -o "$tmp/usr2.exr" --stats "$tmp/usr2.json" \
        >"$tmp/out" 2>"$tmp/err" &
    job=$!
    sleep "$wait_s"
    kill -USR2 "$job"
    ( sleep 30; kill -9 "$job" 2>/dev/null ) &
    watchdog=$!
    wait "$job"
    status=$?
    kill "$watchdog" 2>/dev/null
    if [ "$status" -ne 140 ] || [ ! -s "$tmp/usr2.exr" ] ||
        ! python3 - "$tmp/usr2.json" <<'EOF'; then
import json, sys
s = json.load(open(sys.argv[1]))
assert s["interrupted"] and 0 < s["spp"] < 100000 and s["spp"] % 8 == 0, s
assert s.get("particles", 0) < 4e9, s
EOF
        fail "$name" "status $status: $(tail -3 "$tmp/err"; head -c 300 "$tmp/usr2.json" 2>/dev/null)"
    else pass "$name"; fi
}
stop_with_usr2 "SIGUSR2 during adaptive sampling keeps the image" 5 --mode pt --spp 100000 --width 48 cornell
stop_with_usr2 "SIGUSR2 during the particle trace keeps the image" 5 --mode lv --particles 4e9 --spp 100000 \
    --width 48 cornell

# build/lvcl itself does not need MPI.
if ldd "$lvcl" | grep -q libmpi; then fail "lvcl without MPI" "$(ldd "$lvcl" | grep libmpi)"
else pass "lvcl without MPI"; fi
