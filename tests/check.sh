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
check_summary() { # check_summary NAME
    echo "$1: $passed passed, $failed failed"
    [ "$failed" = 0 ]
}
