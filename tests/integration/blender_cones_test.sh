#!/usr/bin/env bash
# Blender 3.4 headless, as a technical artist opens an asset: File > Import > OpenVDB
# (bpy.ops.object.volume_import, default settings) of an asset of the authors' rig, then what
# View > Frame All frames (the object's box: every grid's leaf nodes). Checks that the box is the
# beams' (the density grid's, read with pyopenvdb) and the grid the viewport draws is theirs,
# that it holds both lamps, and that each
# lamp's bright lobe in the imported grid points along that lamp's axis in Blender's frame
# (camera (x, y, z) -> (x, -y, -z)) within 2 degrees: the mean direction from the lamp to the
# voxels within 0.45 m of it whose density is at least 0.6.
set -euo pipefail
ds=$1 work=$2 src=$3
command -v blender >/dev/null || { echo "SKIP: blender is not installed (scripts/install-deps.sh --tests installs it)"; exit 77; }
rm -rf "$work"; mkdir -p "$work"
"$ds" bake --camera "$src/volumes/cameras/authors-800.yaml" \
  --rig "$src/volumes/rigs/authors-testset.yaml" --water deep:clear --no-check \
  --xy-step 32 --depth-samples 16 -o "$work/a.vdb" >/dev/null
"$ds" info --json "$work/a.vdb" > "$work/a.json"
cat > "$work/frame.py" <<'PY'
import json, sys
import bpy, mathutils
path, out = sys.argv[sys.argv.index("--") + 1:]
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj, do_unlink=True)
bpy.ops.object.volume_import(filepath=path, files=[])
obj = [o for o in bpy.context.scene.objects if o.type == "VOLUME"][0]
obj.data.grids.load()
corners = [obj.matrix_world @ mathutils.Vector(c) for c in obj.bound_box]
json.dump({"grids": sorted(g.name for g in obj.data.grids),
           "shown": obj.data.grids[obj.data.grids.active_index].name,  # the viewport draws it
           "min": [min(c[a] for c in corners) for a in range(3)],
           "max": [max(c[a] for c in corners) for a in range(3)]}, open(out, "w"))
PY
blender -b --factory-startup --python "$work/frame.py" -- "$work/a.vdb" "$work/frame.json" \
  > "$work/blender.log" 2>&1 || { tail -20 "$work/blender.log"; exit 1; }
/usr/bin/python3 - "$work" <<'PY'
import json, math, sys
import numpy as np
import pyopenvdb as vdb
work = sys.argv[1]
frame = json.load(open(f"{work}/frame.json"))
info = json.load(open(f"{work}/a.json"))
assert frame["grids"] == ["density", "water_backscatter"], frame["grids"]
assert frame["shown"] == "density", frame["shown"]  # the viewport shows the beams
g = vdb.read(f"{work}/a.vdb", "density")
lo, hi = g.evalActiveVoxelBoundingBox()
leaf_lo = [x & ~7 for x in lo]
leaf_hi = [(x & ~7) + 7 for x in hi]
w_lo = g.transform.indexToWorld(leaf_lo)
w_hi = g.transform.indexToWorld(leaf_hi)
print(f"Frame All box {np.round(frame['min'], 3)} .. {np.round(frame['max'], 3)}; "
      f"beams {np.round(w_lo, 3)} .. {np.round(w_hi, 3)}")
h = g.transform.voxelSize()[0]
for a in range(3):  # Frame All frames the beams: no other grid widens the box
    assert frame["min"][a] >= w_lo[a] - 8 * h - 1e-4 and frame["max"][a] <= w_hi[a] + 8 * h + 1e-4, a
# The voxels, as positions in Blender's frame (the grid's own transform, as Blender uses it).
ijk, dens = [], []
for it in g.citerOnValues():
    if it.count == 1:
        ijk.append(it.min); dens.append(it.value)
ijk, dens = np.array(ijk, float), np.array(dens)
pos = np.array([g.transform.indexToWorld(tuple(p)) for p in ijk])
for lamp in info["bake"]["rig"]["lights"]:
    p = np.array(lamp["position"]) * [1, -1, -1]
    axis = np.array(lamp["direction"]) * [1, -1, -1]
    axis /= np.linalg.norm(axis)
    for a in range(3):  # the lamps sit on the camera's plane, the box's top to a voxel
        assert frame["min"][a] - h <= p[a] <= frame["max"][a] + h, (lamp["name"], "outside")
    d = pos - p
    near = (np.linalg.norm(d, axis=1) < 0.45) & (dens >= 0.6)
    assert near.sum() >= 20, (lamp["name"], int(near.sum()))
    m = d[near].mean(axis=0)
    m /= np.linalg.norm(m)
    deg = math.degrees(math.acos(min(1.0, float(m @ axis))))
    print(f"lamp {lamp['name']}: beam {np.round(m, 3)}, axis in Blender's frame "
          f"{np.round(axis, 3)}, {deg:.2f} degrees apart ({int(near.sum())} voxels)")
    assert deg < 2.0, (lamp["name"], deg)
PY
echo "blender_cones: OK"
