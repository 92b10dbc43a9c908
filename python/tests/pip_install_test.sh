#!/usr/bin/env bash
# `pip install .` into a virtual environment, offline (CTest: python_pip): Debian's setuptools
# and wheel build the package (pyproject.toml, setup.py) from this build folder
# (DEEPSEA_BUILD_DIR: nothing is compiled again), then the venv's Python, with no PYTHONPATH,
# imports the installed package, which loads nothing from the build tree (its OpenImageIO
# module included), and renders a frame as the build tree's module does. The venv has the
# system site packages: NumPy from Debian (python3-numpy) is installed there, and pip offline
# has no other. Exit 77 (skipped) without python3-venv or NumPy.
set -euo pipefail
python=$1 src=$2 build=$3 work=$4
fail() { echo "FAIL: $*"; exit 1; }
"$python" -c "import numpy" 2>/dev/null || { echo "SKIP: $python has no numpy"; exit 77; }
"$python" -c "import ensurepip, venv" 2>/dev/null ||
  { echo "SKIP: $python has no venv (apt-get install python3-venv)"; exit 77; }
rm -rf "$work"; mkdir -p "$work/src/python"
# What `pip install .` reads, copied: the source tree is not written to (setuptools' egg-info).
cp "$src"/{pyproject.toml,setup.py,README.md,CMakeLists.txt} "$work/src/"
cp -r "$src/python/deepsea" "$work/src/python/"
"$python" -m venv --system-site-packages "$work/venv"
env -u PYTHONPATH DEEPSEA_BUILD_DIR="$build" "$work/venv/bin/python" -m pip install -q \
  --no-build-isolation --no-index "$work/src"
site=$("$work/venv/bin/python" -c "import sysconfig; print(sysconfig.get_paths()['purelib'])")
for f in __init__.py _deepsea.pyi py.typed libdeepsea_oiio.so; do
  [[ -f $site/deepsea/$f ]] || fail "$site/deepsea/$f is not installed"
done
mod=$(find "$site/deepsea" -name '_deepsea*.so' | head -1)
[[ -n $mod ]] || fail "no extension in $site/deepsea"
build_abs=$(cd "$build" && pwd -P)
if ldd "$mod" | grep -q -e "not found" -e "$build_abs"; then
  ldd "$mod"; fail "$mod loads a library that is missing or in the build tree"
fi
# The same frame from the in-tree module and from the installed package.
cd "$work"
cat > frame.py <<'PY'
import os
import sys

import numpy as np

import deepsea

h, w = 30, 40
cam = {"width": w, "height": h, "fx": 30.0, "fy": 30.0, "cx": 19.5, "cy": 14.5}
rig = {"name": "one", "lights": [{"position": [0.3, 0.0, 0.0], "direction": [0.0, 0.0, 1.0],
                                  "intensity": [1.0, 1.0, 1.0],
                                  "rid": {"gaussian": {"sigma_deg": 35}}}]}
asset = deepsea.bake({"camera": cam, "rig": rig}, water="jerlov:IB", xy_step=8,
                     depth_samples=8, check=False)
v, u = np.mgrid[0:h, 0:w]
rgb = np.stack([(u * 6) % 256, (v * 8) % 256, np.full((h, w), 90)], axis=2).astype(np.uint8)
depth = (2.0 + 0.02 * u).astype(np.float32)
out = sys.argv[1]
# TIFF through the OpenImageIO module: written and read back (the module beside the extension).
deepsea.write_image(out + ".tif", rgb)
np.save(out + "_depth.npy", depth)
frame = deepsea.read_frame(out + ".tif", out + "_depth.npy")
assert frame["rgb"].shape == (h, w, 3) and frame["encoding"] == "linear"  # decoded, as the CLI
np.save(out + ".npy", deepsea.Renderer(asset).render(**frame)["final"])
maps = open("/proc/self/maps").read()
plugin = [line.split()[-1] for line in maps.splitlines() if "libdeepsea_oiio" in line]
print(deepsea.__file__, plugin[0] if plugin else "no plugin")
PY
installed=$(env -u PYTHONPATH -u DEEPSEA_OIIO_PLUGIN "$work/venv/bin/python" frame.py installed)
in_tree=$(PYTHONPATH="$build/python/module" "$python" frame.py in_tree)
echo "installed: $installed"
echo "in tree:   $in_tree"
[[ $installed == "$site/deepsea/__init__.py $site/deepsea/libdeepsea_oiio.so" ]] ||
  fail "the installed package is not the one imported, or its OpenImageIO module is another"
"$python" -c "
import sys, numpy as np
a, b = np.load('installed.npy'), np.load('in_tree.npy')
assert a.std() > 0 and (a == b).all(), 'the installed package renders another frame'
"
echo "pip install: OK"
