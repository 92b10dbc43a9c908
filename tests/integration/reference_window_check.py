#!/usr/bin/python3
"""validate.py --confirm path-traces a bin again alone, in a window of the row's camera
(tools/reference/validate.py, `camera(..., window=...)`). The window must cast the same rays
through the same pixels as the full camera: `deepsea reference` (exact single scattering) of a
window equals the full frame's pixels there (water light and direct signal), and the window shifted by one pixel does not.

usage: reference_window_check.py DEEPSEA_BIN WORKDIR SOURCE_DIR
"""
import os
import subprocess
import sys

import numpy as np

deepsea, work, src = sys.argv[1:4]
sys.path.insert(0, os.path.join(src, "tools", "reference"))
from compare_baked import read_layer  # noqa: E402
from validate import camera, write_scene  # noqa: E402

# a CI row: clear water, the two spots, 16x12 px, a plane at 3 m; and the AUV rig's asymmetry
ROWS = {"two-spots": ("clear", "two-spots", "16x12", 64.5, 3.0, 512),
        "auv": ("coastal", "auv", "16x12", 64.5, 3.0, 512)}
WINDOW = (4, 8, 4, 4)  # rows 4-7, columns 8-11


def trace(d, row, cam):
    setup, rgb, depth = write_scene(d, row, cam, row[4])
    out = os.path.join(d, "ref.exr")
    subprocess.run([deepsea, "reference", "--config", setup, "--rgb", rgb, "--depth", depth,
                    "--z-max", "20", "--layers", out], check=True, stdout=subprocess.DEVNULL)
    return out


failed = []
for name, row in ROWS.items():
    w, h = map(int, row[2].split("x"))
    full = trace(os.path.join(work, name, "full"), row, camera(w, h, row[3]))
    win = trace(os.path.join(work, name, "window"), row, camera(w, h, row[3], WINDOW))
    r0, c0, wh, ww = WINDOW
    # per pixel layers only: the exact reference's `forward` (hence `final`) blurs the frame it
    # is given; the path tracer's is transport on the whole plane, the same in any window
    for layer in ("backscatter", "direct"):
        f, g = read_layer(full, layer), read_layer(win, layer)
        same = np.abs(g - f[r0:r0 + wh, c0:c0 + ww]).max() / np.abs(g).max()
        shifted = np.abs(g - f[r0:r0 + wh, c0 + 1:c0 + 1 + ww]).max() / np.abs(g).max()
        print(f"{name} {layer}: window vs its pixels {same:.2e}, vs one pixel over {shifted:.2e}")
        if not same <= 1e-5:
            failed.append(f"{name} {layer}: window differs from its pixels by {same:.2e}")
        if not shifted >= 1e-3:
            failed.append(f"{name} {layer}: the field is too flat to tell a shift ({shifted:.2e})")
if failed:
    print("FAIL: " + "; ".join(failed))
    sys.exit(1)
