#!/usr/bin/env bash
# Runs the Python module's tests with pytest (CTest: python_module). Exit 77 (skipped) when the
# interpreter has no pytest or NumPy.
set -euo pipefail
python=$1 tests=$2 work=$3
for m in pytest numpy; do
  if ! "$python" -c "import $m" 2>/dev/null; then
    echo "SKIP: $python has no $m (apt-get install python3-$m)"
    exit 77
  fi
done
# Nothing written into the source tree (no __pycache__ beside the tests).
export PYTHONDONTWRITEBYTECODE=1
rm -rf "$work"; mkdir -p "$work"
cd "$work"
exec "$python" -m pytest -q -p no:cacheprovider --basetemp="$work/tmp" "$tests"
