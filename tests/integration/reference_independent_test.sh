#!/usr/bin/env bash
# deepsea reference vs an independent NumPy implementation of the same equations (planes,
# two lamps, HG, isotropic and Petzold coastal water): direct <= 1e-3, backscatter <= 2e-3 relative, max.
set -euo pipefail
deepsea=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
/usr/bin/python3 "$src/tests/integration/reference_check.py" "$deepsea" "$work"
