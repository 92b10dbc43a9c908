#!/usr/bin/env bash
# Blender 3.4 headless opens a baked asset with tools/blender/open_asset.py: the density and
# color grids load, and the rendered light cones are visible (bright centre, dark corner).
set -euo pipefail
ds=$1 work=$2 src=$3
command -v blender >/dev/null || { echo "FAIL: blender is not installed (scripts/install-deps.sh --tests installs it)"; exit 1; }
rm -rf "$work"; mkdir -p "$work"
"$ds" bake --config "$src/volumes/demo.yaml" --xy-step 32 --depth-samples 16 -o "$work/a.vdb" >/dev/null
blender -b --factory-startup --python "$src/tools/blender/open_asset.py" -- "$work/a.vdb" \
  --render "$work/side.png" --view side --samples 8 --resolution 160 > "$work/blender.log" 2>&1 || {
  tail -20 "$work/blender.log"; exit 1; }
grep -q "^grid density FLOAT" "$work/blender.log" || { echo "FAIL: density grid not loaded"; cat "$work/blender.log"; exit 1; }
grep -q "^grid color VECTOR_FLOAT" "$work/blender.log" || { echo "FAIL: color grid not loaded"; exit 1; }
/usr/bin/python3 - "$work/side.png" <<'PY'
import sys, numpy as np, OpenImageIO as oiio
px = oiio.ImageBuf(sys.argv[1]).get_pixels(oiio.FLOAT)[:, :, :3]
h, w = px.shape[:2]
cone = px[h // 3: 2 * h // 3, w // 3: 2 * w // 3].mean()
corner = px[: h // 8, : w // 8].mean()
print(f"cone {cone:.4f} corner {corner:.4f}")
assert cone > 0.03 and cone > 3 * corner, "the light cones are not visible"
PY
echo "blender: OK"
