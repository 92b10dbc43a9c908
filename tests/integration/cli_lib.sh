# Helpers for the CLI tests (sourced; needs $work).

# expect_fail NAME CMD...: CMD must exit non-zero with exactly one line on stderr.
expect_fail() {
  local name=$1; shift
  set +e
  "$@" >"$work/out.txt" 2>"$work/err.txt"
  local rc=$?
  set -e
  if [[ $rc -eq 0 ]]; then echo "FAIL $name: exit 0"; exit 1; fi
  if [[ $(wc -l <"$work/err.txt") -ne 1 ]]; then echo "FAIL $name: stderr:"; cat "$work/err.txt"; exit 1; fi
  echo "ok $name (exit $rc): $(cat "$work/err.txt")"
}

# expect_absent PATH...: none of the paths exists (no half-written output).
expect_absent() {
  local p
  for p in "$@"; do
    if [[ -e $p ]]; then echo "FAIL: $p was written"; exit 1; fi
  done
}
