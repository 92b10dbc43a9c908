#!/usr/bin/env bash
# The validation table's reduced version (docs/validation.md):
# tools/reference/validate.py --set ci bakes, renders and path-traces a clear plane at 3 m and a
# turbid plane at 2 m on a 16x12 camera, and fails where water, surface or final misses the
# 5 % target in image sums by more than 3 of the path tracer's standard errors.
set -euo pipefail
deepsea=$1 work=$2 src=$3
py=/usr/bin/python3
if ! $py -c 'import numpy, OpenImageIO' 2>/dev/null; then
  echo "SKIP: $py with numpy and OpenImageIO is absent"; exit 77
fi
rm -rf "$work"; mkdir -p "$work"
$py "$src/tools/reference/validate.py" "$deepsea" "$work" --set ci --threads 1 --check
