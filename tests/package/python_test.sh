#!/usr/bin/env bash
# The Python module from the installed prefix alone: with PYTHONPATH=<prefix>/<python dir>,
# `import deepsea` finds the installed module (not the build tree's), bakes a tiny asset and
# renders a frame from NumPy arrays into NumPy layers. The module loads no library from the
# build tree.
set -euo pipefail
python=$1 build=$2 prefix=$3 pydir=$4
fail() { echo "FAIL: $*"; exit 1; }
"$python" -c "import numpy" 2>/dev/null || { echo "SKIP: $python has no numpy"; exit 77; }
site=$prefix/$pydir
mod=$(find "$site/deepsea" -maxdepth 1 -name '_deepsea*.so' | head -1)
[[ -n $mod ]] || fail "no deepsea module in $site"
build_abs=$(cd "$build" && pwd -P)
if ldd "$mod" | grep -q -e "not found" -e "$build_abs"; then
  ldd "$mod"; fail "$mod loads a library that is missing or in the build tree"
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
env -u PYTHONHOME PYTHONPATH="$site" "$python" - "$site" <<'PY'
import os
import sys

import numpy as np

import deepsea

site = os.path.realpath(sys.argv[1])
assert os.path.realpath(deepsea.__file__).startswith(site + os.sep), deepsea.__file__
cam = {"width": 40, "height": 30, "fx": 30.0, "fy": 30.0, "cx": 19.5, "cy": 14.5}
rig = {"name": "one", "lights": [{"position": [0.3, 0.0, 0.0], "direction": [0.0, 0.0, 1.0],
                                  "intensity": [1.0, 1.0, 1.0],
                                  "rid": {"gaussian": {"sigma_deg": 35}}}]}
asset = deepsea.bake({"camera": cam, "rig": rig}, water="jerlov:IB", xy_step=8,
                     depth_samples=8, check=False)
rgb = np.full((30, 40, 3), 128, np.uint8)
depth = np.full((30, 40), 2.5, np.float32)
layers = deepsea.Renderer(asset).render(rgb, depth)
assert layers["final"].shape == (30, 40, 3) and layers["final"].dtype == np.float32
assert layers["depth"].shape == (30, 40) and np.isfinite(layers["final"]).all()
assert (layers["final"] > 0).all()
print(f"deepsea {deepsea.__version__} from {deepsea.__file__}: rendered "
      f"{', '.join(sorted(layers))}")
PY
echo "package python: OK"
