# check.sh: the assertion helpers of the shell tests (sourced): a temporary folder as the working
# folder, counts, and `run NAME EXPECTED_RC CMD...`, which keeps CMD's stdout and stderr in
# $tmp/out and $tmp/err; check_summary prints the closing line and sets the exit status.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
passed=0
failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*" >&2; }
run() {
    local name=$1 want=$2
    shift 2
    "$@" >"$tmp/out" 2>"$tmp/err"
    local rc=$?
    if [ "$rc" = "$want" ]; then ok; else bad "$name: exit $rc, want $want; stderr: $(head -c 600 "$tmp/err")"; fi
}
has() { # has NAME FILE TEXT: TEXT is in FILE
    if grep -qF -- "$3" "$2"; then ok; else bad "$1: '$3' not in $(basename "$2"): $(head -c 400 "$2")"; fi
}
device_cuts_loops() { # device_cuts_loops TRAZADOR: "true" when the default device's driver stops
    # loops silently (lavapipe 22.3; `devices` says what the probe found), else "false"
    if "$1" devices 2>/dev/null | grep -A1 '^\*' | grep -q "loops stop silently"; then echo true; else echo false; fi
}
check_summary() { # check_summary NAME
    echo "$1: $passed passed, $failed failed"
    [ "$failed" = 0 ]
}
