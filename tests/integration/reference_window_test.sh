#!/usr/bin/env bash
# validate.py --confirm's windows (tools/reference/validate.py): a window of a row's camera casts
# the same rays through the same pixels as the full camera (exact single scattering, 1e-5), and a
# window one pixel over does not; compare() names the resolved bins over the target.
set -euo pipefail
deepsea=$1 work=$2 src=$3
py=/usr/bin/python3
if ! $py -c 'import numpy, OpenImageIO' 2>/dev/null; then
  echo "SKIP: $py with numpy and OpenImageIO is absent"; exit 77
fi
rm -rf "$work"; mkdir -p "$work"
$py "$src/tests/integration/reference_window_check.py" "$deepsea" "$work" "$src"
