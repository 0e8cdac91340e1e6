#!/bin/sh
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
tests_dir=$(dirname "$0")
log=$(mktemp)
passed=0
failed=0

count() { # $1: name of what ran, $2: its exit status, $3: seconds it took; reads the log
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
    echo "-- $1: $p passed, $f failed ($3 s)"
}

# Whether test NAME ($1, without "test_") was asked for.
wanted() {
    [ -z "$names" ] && return 0
    for n in $names; do [ "$n" = "$1" ] && return 0; done
    return 1
}

programs=$(ls "$build"/tests/test_* 2>/dev/null)
ran=0
for t in $programs; do
    name=$(basename "$t")
    wanted "${name#test_}" || continue
    ran=$((ran + 1))
    start=$(date +%s)
    "$t" "$tests_dir" >"$log" 2>"$log.err"
    status=$?
    [ -s "$log.err" ] && [ "$status" -ne 0 ] && cat "$log.err" >>"$log"
    count "$name" "$status" $(($(date +%s) - start))
done

# The shell tests: tests/app/NAME_tests.sh.
for script in "$tests_dir"/app/*_tests.sh; do
    name=$(basename "$script" .sh)
    wanted "${name%_tests}" || wanted "$name" || continue
    [ -n "$asan" ] && { [ "$name" = oclgrind_tests ] || [ "$name" = fuzz_tests ] || [ "$name" = mpi_tests ]; } &&
        continue
    ran=$((ran + 1))
    start=$(date +%s)
    "$script" "$build" >"$log" 2>&1
    status=$?
    count "$name" "$status" $(($(date +%s) - start))
done

rm -f "$log" "$log.err"
if [ "$ran" -eq 0 ]; then
    echo "FAIL tests/run.sh: no test is named$names (tests: $(cd "$build/tests" 2>/dev/null && ls -d test_* | sed 's/^test_//' | tr '\n' ' ')$(cd "$tests_dir/app" && ls *_tests.sh | sed 's/_tests.sh$//' | tr '\n' ' '))"
    failed=1
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
