"""Run by blender_test.sh in `blender -b --factory-startup`: imports each file as a user would
(File > Import > OpenVDB, bpy.ops.object.volume_import, default settings) and checks the
bounding box Blender gives the new object (the union of its grids' OpenVDB leaf nodes: what
View > Frame All frames) against the frustum extent of the asset's camera, computed here from
the intrinsics and z_max alone (docs/asset-format.md, "World frame and extent").

blender -b --factory-startup --python blender_import_check.py -- CASES.json
CASES.json: a list of {"file", "camera": {width, height, fx, fy, cx, cy}, "z_max",
"grids": [names the file must hold], "fill": fraction of the extent the box must span}
"""
import json
import sys

import bpy
import mathutils


def extent(cam, z_max):
    """World box (x right, y up, looking down -z) of the view from the camera centre to
    planar depth z_max through the image's outer pixel edges."""
    xs = [0.0, (-0.5 - cam["cx"]) / cam["fx"] * z_max,
          (cam["width"] - 0.5 - cam["cx"]) / cam["fx"] * z_max]
    ys = [0.0, (0.5 + cam["cy"]) / cam["fy"] * z_max,  # world y = -camera y
          -(cam["height"] - 0.5 - cam["cy"]) / cam["fy"] * z_max]
    return [min(xs), min(ys), -z_max], [max(xs), max(ys), 0.0]


def main():
    cases = json.load(open(sys.argv[sys.argv.index("--") + 1]))
    failures = []
    for case in cases:
        for obj in list(bpy.data.objects):
            bpy.data.objects.remove(obj, do_unlink=True)
        bpy.ops.object.volume_import(filepath=case["file"], files=[])
        objs = [o for o in bpy.context.scene.objects if o.type == "VOLUME"]
        if len(objs) != 1:
            failures.append(f"{case['file']}: {len(objs)} volume objects after the import")
            continue
        obj = objs[0]
        obj.data.grids.load()
        names = sorted(g.name for g in obj.data.grids)
        # Object space = world: the import puts the object at the origin, unrotated.
        corners = [obj.matrix_world @ mathutils.Vector(c) for c in obj.bound_box]
        lo = [min(c[a] for c in corners) for a in range(3)]
        hi = [max(c[a] for c in corners) for a in range(3)]
        elo, ehi = extent(case["camera"], case["z_max"])
        print(f"{case['file']}: grids {names}, box {[round(x, 3) for x in lo]} .. "
              f"{[round(x, 3) for x in hi]}, extent {[round(x, 3) for x in elo]} .. "
              f"{[round(x, 3) for x in ehi]}")
        if names != sorted(case["grids"]):
            failures.append(f"{case['file']}: grids {names}, expected {sorted(case['grids'])}")
        for a in range(3):
            size = ehi[a] - elo[a]
            tol = 1e-5 * size  # Blender keeps the box in single precision
            if lo[a] < elo[a] - tol or hi[a] > ehi[a] + tol:
                failures.append(f"{case['file']}: axis {'xyz'[a]} {lo[a]:.6g} .. {hi[a]:.6g} "
                                f"leaves the frustum extent {elo[a]:.6g} .. {ehi[a]:.6g}")
            if not hi[a] - lo[a] > case["fill"] * size:
                failures.append(f"{case['file']}: axis {'xyz'[a]} spans {hi[a] - lo[a]:.6g} m, "
                                f"not more than {case['fill']} of the extent ({size:.6g} m)")
    for f in failures:
        print("FAIL:", f)
    print(f"import check: {len(cases)} files, {len(failures)} failures")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
