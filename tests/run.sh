#!/usr/bin/env bash
# Runs lvcl's tests: every test program in BUILD/tests (built from
# tests/<layer>/test_<name>.c; each prints PASS and FAIL lines) and the
# shell tests (tests/app/*_tests.sh), then one line of totals. Each
# program gets this folder as its argument.
#   tests/run.sh BUILD [--asan] [NAME...]
#   --asan: a sanitizer build: every program and the shell tests but
#           oclgrind and fuzz (which bring their own checks) and mpi
#           (Open MPI does not run under ASan; see the Makefile)
#   NAME:   only these tests: a program's name with or without "test_"
#           (golden, test_render, ...), or NAME for the shell test
#           tests/app/NAME_tests.sh (cli, oclgrind, fuzz)
#   make test T=NAME runs the same.
# Tests run TEST_JOBS at a time (default 2): much of the suite leaves a
# core idle (Oclgrind, PoCL's kernel compiler, the host's scene builds,
# many short lvcl runs in the shell tests), so two lanes finish sooner.
# Each test's lines are printed together when it ends.
build=${1:-build}
[ $# -gt 0 ] && shift
asan=
names=
for a in "$@"; do
    case "$a" in
    --asan) asan=1 ;;
    *) names="$names ${a#test_}" ;;
    esac
done
jobs=${TEST_JOBS:-2}
tests_dir=$(dirname "$0")
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
passed=0
failed=0

# Whether test NAME ($1, without "test_") was asked for.
wanted() {
    [ -z "$names" ] && return 0
    for n in $names; do [ "$n" = "$1" ] && return 0; done
    return 1
}

# What to run, one "name command" per line. The longest tests start first
# so that the lanes end together (seconds measured on two cores).
slow_first="test_see_through cli_tests mpi_tests oclgrind_tests test_light_volume test_render test_two_rooms"
list=
for t in "$build"/tests/test_*; do
    [ -x "$t" ] || continue
    name=$(basename "$t")
    wanted "${name#test_}" && list="$list$name $t $tests_dir"$'\n'
done
for script in "$tests_dir"/app/*_tests.sh; do
    name=$(basename "$script" .sh)
    wanted "${name%_tests}" || wanted "$name" || continue
    [ -n "$asan" ] && case "$name" in oclgrind_tests | fuzz_tests | mpi_tests) continue ;; esac
    list="$list$name $script $build"$'\n'
done
ordered=
for s in $slow_first; do ordered="$ordered$(grep "^$s " <<<"$list")"$'\n'; done
ordered="$ordered$(grep -v -E "^($(tr ' ' '|' <<<"$slow_first")) " <<<"$list")"
ordered=$(grep -v '^$' <<<"$ordered")

# Runs one test in the background: its output, exit status and seconds go
# to files under $logs named after it.
start_test() { # name, command...
    local name=$1
    shift
    (
        start=$(date +%s)
        "$@" </dev/null >"$logs/$name.out" 2>"$logs/$name.err"
        echo $? >"$logs/$name.status.tmp"
        echo $(($(date +%s) - start)) >"$logs/$name.secs"
        mv "$logs/$name.status.tmp" "$logs/$name.status"
    ) &
}

# Prints and counts a finished test: its FAIL and SKIP lines, a FAIL for a
# non-zero exit that named no failed check, and its totals.
report() { # name
    local name=$1 out="$logs/$1.out" status p f
    status=$(cat "$logs/$name.status")
    p=$(grep -c '^PASS ' "$out")
    f=$(grep -c '^FAIL ' "$out")
    grep -E '^(FAIL|SKIP) ' "$out"
    if [ "$status" -ne 0 ] && [ "$f" -eq 0 ]; then
        echo "FAIL $name: exited with status $status without naming a failed check"
        cat "$logs/$name.err" "$out" | tail -5
        f=1
    fi
    passed=$((passed + p))
    failed=$((failed + f))
    echo "-- $name: $p passed, $f failed ($(cat "$logs/$name.secs") s)"
}

running=()
ran=0
while read -r name cmd arg; do
    [ -n "$name" ] || continue
    while [ ${#running[@]} -ge "$jobs" ]; do
        wait -n 2>/dev/null || true
        still=()
        for r in "${running[@]}"; do
            if [ -e "$logs/$r.status" ]; then report "$r"; else still+=("$r"); fi
        done
        running=("${still[@]}")
    done
    start_test "$name" "$cmd" "$arg"
    running+=("$name")
    ran=$((ran + 1))
done <<<"$ordered"
wait
for r in "${running[@]}"; do report "$r"; done

if [ "$ran" -eq 0 ]; then
    echo "FAIL tests/run.sh: no test is named$names (tests: $(cd "$build/tests" 2>/dev/null && ls -d test_* | sed 's/^test_//' | tr '\n' ' ')$(cd "$tests_dir/app" && ls *_tests.sh | sed 's/_tests.sh$//' | tr '\n' ' '))"
    failed=1
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
