#!/usr/bin/env python3
"""Path-traces windows of a validation row's camera, each alone (docs/validation.md).

Usage: trace_windows.py DEEPSEA WORK ROW --paths N --seed S [--threads T] R,C,H,W [R,C,H,W ...]
Each window (first row R, first column C, H rows, W columns) is validate.py's
camera(window=...): the row's own rays through the same pixels, its scene written by
validate.py's write_scene into WORK/ROW/win-R-C-H-W, traced by `deepsea reference --scattering
multiple` with N paths per pixel and seed S + k for the k-th window (0-based), so that no two
windows share a seed. A window already traced there is kept. Prints, per window, the argument
that combine_traces.py takes to pool it into the row's whole image (PATH@R,C): a trace too long
for a loaded machine runs as windows that each finish, the bins where they lie first.
Debian's python3, numpy, OIIO.
"""

import argparse
import os
import sys
import time

from validate import TABLE, Z_MAX, camera, run, write_scene


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("deepsea")
    ap.add_argument("work")
    ap.add_argument("row", choices=sorted(TABLE))
    ap.add_argument("--paths", type=int, required=True)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("windows", nargs="+", metavar="R,C,H,W")
    a = ap.parse_args()
    row = TABLE[a.row]
    _, _, size, fov, z, _ = row
    w, h = map(int, size.split("x"))
    for k, spec in enumerate(a.windows):
        r0, c0, wh, ww = (int(x) for x in spec.split(","))
        if r0 < 0 or c0 < 0 or wh < 1 or ww < 1 or r0 + wh > h or c0 + ww > w:
            sys.exit(f"window {spec} is not inside the {size} camera")
        d = os.path.join(a.work, a.row, f"win-{r0}-{c0}-{wh}-{ww}")
        pt = os.path.join(d, "pt.exr")
        if not os.path.exists(pt):
            setup, rgb, depth = write_scene(d, row, camera(w, h, fov, (r0, c0, wh, ww)), z)
            t = run([a.deepsea, "reference", "--config", setup, "--rgb", rgb, "--depth", depth,
                     "--scattering", "multiple", "--paths", str(a.paths), "--seed",
                     str(a.seed + k), "--z-max", str(Z_MAX), "--layers", pt + ".part.exr",
                     "--threads", str(a.threads)])
            os.replace(pt + ".part.exr", pt)
            print(f"{spec}: {t:.0f} s {time.strftime('%H:%M:%S')}", file=sys.stderr, flush=True)
        print(f"{pt}@{r0},{c0}")


if __name__ == "__main__":
    main()
