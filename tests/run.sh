#!/bin/sh
# Runs lvcl's tests: every test program in BUILD/tests (each prints PASS and
# FAIL lines) and the command-line tests, then one line of totals.
#   tests/run.sh BUILD [--asan]     --asan: only the tests that matter under sanitizers
build=${1:-build}
asan=${2:-}
tests_dir=$(dirname "$0")
log=$(mktemp)
passed=0
failed=0

count() { # $1: name of what ran, $2: its exit status; reads the log
    p=$(grep -c '^PASS ' "$log")
    f=$(grep -c '^FAIL ' "$log")
    grep -E '^(FAIL|SKIP) ' "$log"
    if [ "$2" -ne 0 ] && [ "$f" -eq 0 ]; then
        echo "FAIL $1: exited with status $2 without naming a failed check"
        tail -5 "$log"
        f=1
    fi
    passed=$((passed + p))
    failed=$((failed + f))
    echo "-- $1: $p passed, $f failed"
}

if [ -n "$asan" ]; then
    programs="$build/tests/test_gltf_import"
else
    programs=$(ls "$build"/tests/test_* 2>/dev/null)
fi
for t in $programs; do
    "$t" "$tests_dir" >"$log" 2>"$log.err"
    status=$?
    [ -s "$log.err" ] && [ "$status" -ne 0 ] && cat "$log.err" >>"$log"
    count "$(basename "$t")" "$status"
done

"$tests_dir/cli_tests.sh" "$build" >"$log" 2>&1
count cli_tests $?

rm -f "$log" "$log.err"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
