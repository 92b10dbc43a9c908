#!/usr/bin/env bash
# Blender 3.4 headless, as a user would open deepsea assets:
# 1. File > Import > OpenVDB (bpy.ops.object.volume_import, default settings) of assets in four
#    depth schemes and two cameras (one at 110 degrees): the box Blender frames (every grid's
#    leaf nodes) lies within the frustum extent computed from the asset's camera and spans it;
#    the same for each grid alone (split out with pyopenvdb), so no grid is flat or outside.
# 2. The backscatter grid's (water_backscatter) metadata gives its true camera-space points (docs/asset-format.md).
# 3. tools/blender/open_asset.py opens an asset with deepsea info --json (and without a deepsea
#    binary, from the file's header), and the rendered light cones are visible.
set -euo pipefail
ds=$1 work=$2 src=$3
command -v blender >/dev/null || { echo "SKIP: blender is not installed (scripts/install-deps.sh --tests installs it)"; exit 77; }
rm -rf "$work"; mkdir -p "$work"
rig=$src/volumes/rigs/authors-testset.yaml
camera() {  # name width height fov_deg: a centred pinhole camera
  /usr/bin/python3 - "$work/$1.yaml" "$2" "$3" "$4" <<'PY'
import math, sys
path, w, h, fov = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
f = (w / 2) / math.tan(math.radians(fov / 2))
open(path, "w").write(f"camera:\n  width: {w}\n  height: {h}\n  fx: {f:.6f}\n  fy: {f:.6f}\n"
                      f"  cx: {(w - 1) / 2}\n  cy: {(h - 1) / 2}\n")
PY
}
camera wide 96 72 110
bake() {  # out camera-yaml extra-args...
  local out=$1 cam=$2; shift 2
  "$ds" bake --camera "$cam" --rig "$rig" --water deep:clear --no-check "$@" -o "$work/$out.vdb" >/dev/null
}
demo=$src/volumes/cameras/authors-800.yaml
bake log "$demo" --xy-step 32 --depth-samples 16                        # the default scheme
bake uniform "$demo" --xy-step 32 --depth-samples 16 --depth-scheme uniform
bake wide-sqrt "$work/wide.yaml" --xy-step 8 --depth-samples 16 --depth-scheme sqrt
bake wide-taylor "$work/wide.yaml" --xy-step 8 --depth-samples 16 --depth-scheme taylor
for a in log uniform wide-sqrt wide-taylor; do "$ds" info --json "$work/$a.vdb" > "$work/$a.json"; done

# Cases for Blender: each whole asset, and each of its grids alone (pyopenvdb writes them).
/usr/bin/python3 - "$work" <<'PY'
import json, math, sys
import pyopenvdb as vdb
work = sys.argv[1]
cases = []
for a in ["log", "uniform", "wide-sqrt", "wide-taylor"]:
    info = json.load(open(f"{work}/{a}.json"))
    cam, z_max = info["bake"]["camera"], info["bake"]["lattice"]["z_max"]
    names = [g["name"] for g in info["grids"]]
    assert sorted(names) == ["density", "water_backscatter"], names
    # Whole file: within the extent (every grid lies within the beams' depth, docs/blender.md).
    cases.append({"file": f"{work}/{a}.vdb", "camera": cam, "z_max": z_max, "grids": names,
                  "fill": 0.02})
    for g in vdb.readAllGridMetadata(f"{work}/{a}.vdb"):
        one = f"{work}/{a}.{g.name}.vdb"
        vdb.write(one, [vdb.read(f"{work}/{a}.vdb", g.name)])
        cases.append({"file": one, "camera": cam, "z_max": z_max, "grids": [g.name],
                      "fill": 0.02})

    # The backscatter grid's true camera-space geometry, read from its own metadata as any
    # OpenVDB tool would, is the camera point of pixel (i step, j step) at depth z_k.
    m = vdb.read(f"{work}/{a}.vdb", "water_backscatter").metadata
    z = [float(t) for t in m["deepsea:z_samples"].split()]
    lat = info["bake"]["lattice"]
    assert m["deepsea:depth_scheme"] == lat["depth_scheme"], m["deepsea:depth_scheme"]
    assert m["deepsea:step"] == lat["step"] and len(z) == lat["depth_samples"] + 1
    for zk, want in zip(z, lat["z"]):
        assert abs(zk - want) <= 1e-12 * lat["z_max"], (zk, want)
    for key in ["fx", "fy", "cx", "cy"]:
        assert m["deepsea:" + key] == cam[key], key
    i, j, k = lat["columns"] - 1, 0, lat["depth_samples"]
    x = (i * m["deepsea:step"] - m["deepsea:cx"]) / m["deepsea:fx"] * z[k]
    y = (j * m["deepsea:step"] - m["deepsea:cy"]) / m["deepsea:fy"] * z[k]
    assert x > 0 and y < 0 and z[k] == lat["z_max"], (x, y, z[k])
json.dump(cases, open(f"{work}/cases.json", "w"))
print(f"{len(cases)} import cases")
PY
blender -b --factory-startup --python "$src/tests/integration/blender_import_check.py" -- \
  "$work/cases.json" > "$work/import.log" 2>&1 || { grep -E "FAIL|Error|rror:" "$work/import.log" | head -40; exit 1; }
grep "^import check" "$work/import.log"

# open_asset.py: metadata from deepsea info --json; the light cones render.
blender -b --factory-startup --python "$src/tools/blender/open_asset.py" -- "$work/log.vdb" \
  --deepsea "$ds" --render "$work/side.png" --samples 8 --resolution 160 \
  > "$work/blender.log" 2>&1 || { tail -20 "$work/blender.log"; exit 1; }
grep -q "^grid density FLOAT" "$work/blender.log" || { echo "FAIL: density grid not loaded"; cat "$work/blender.log"; exit 1; }
/usr/bin/python3 - "$work/side.png" <<'PY'
import sys, numpy as np, OpenImageIO as oiio
px = oiio.ImageBuf(sys.argv[1]).get_pixels(oiio.FLOAT)[:, :, :3]
h, w = px.shape[:2]
cone = px[h // 3: 2 * h // 3, w // 3: 2 * w // 3].mean()
corner = px[: h // 8, : w // 8].mean()
print(f"cone {cone:.4f} corner {corner:.4f}")
assert cone > 0.03 and cone > 3 * corner, "the light cones are not visible"
PY
# Without any deepsea binary (not on PATH, no $DEEPSEA): the metadata from the file's header.
env -u DEEPSEA PATH=/usr/bin:/bin blender -b --factory-startup \
  --python "$src/tools/blender/open_asset.py" -- "$work/uniform.vdb" --save "$work/u.blend" \
  > "$work/header.log" 2>&1 || { tail -20 "$work/header.log"; exit 1; }
grep -q "reading the file's header" "$work/header.log" || { echo "FAIL: deepsea found, expected none"; exit 1; }
grep -q "^grid density FLOAT" "$work/header.log" || { echo "FAIL: no density grid"; exit 1; }
echo "blender: OK"
