#!/usr/bin/python3
"""Single scattering vs multiple scattering vs Blender Cycles, side by side, from the work
folders of tests/integration/cycles_check.py (run once with --orders single, once with
--orders all). One row per scene: deepsea single scattering (`deepsea reference`, the paper's
model, forward scatter off), deepsea all orders (`deepsea bake --scattering multiple` +
`render`, forward scatter from the phase function), Cycles all orders (mean over its seeds).
Each row is exposed alike (Cycles' 99th percentile at 0.9), sRGB, enlarged without smoothing.

usage: cycles_comparison.py OUT.png SINGLE_WORK ALL_WORK [scene ...]
       (default scenes: clear-plane coastal-plane)
"""
import glob
import os
import sys

import numpy as np
import OpenImageIO as oiio

SCALE = 6  # pixels per image pixel in the figure
GAP = 6


def read_rgb(path, prefix):
    inp = oiio.ImageInput.open(path)
    if inp is None:
        sys.exit(f"cannot read {path}: {oiio.geterror()}")
    names = inp.spec().channelnames
    px = inp.read_image(format="float")
    inp.close()
    return np.stack([px[..., names.index(f"{prefix}.{c}")] for c in "RGB"], axis=-1)


def srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    out, single, every = sys.argv[1:4]
    scenes = sys.argv[4:] or ["clear-plane", "coastal-plane"]
    rows = []
    for s in scenes:
        cycles = [read_rgb(p, "ViewLayer.Combined")
                  for p in sorted(glob.glob(os.path.join(every, s, "cycles_all_seed*.exr")))]
        if not cycles:
            sys.exit(f"no Cycles renders in {os.path.join(every, s)}")
        tiles = [read_rgb(os.path.join(single, s, "reference.exr"), "final"),
                 read_rgb(os.path.join(every, s, "baked_all.exr"), "final"),
                 np.mean(cycles, axis=0)]
        k = 0.9 / max(np.percentile(tiles[2], 99), 1e-12)
        rows.append([srgb(k * t) for t in tiles])
    h, w = rows[0][0].shape[:2]
    H, W = h * SCALE, w * SCALE
    fig = np.ones((len(rows) * (H + GAP) - GAP, 3 * (W + GAP) - GAP, 3), dtype=np.float32)
    for r, row in enumerate(rows):
        for c, tile in enumerate(row):
            big = np.repeat(np.repeat(tile, SCALE, axis=0), SCALE, axis=1)
            y, x = r * (H + GAP), c * (W + GAP)
            fig[y:y + H, x:x + W] = big
    spec = oiio.ImageSpec(fig.shape[1], fig.shape[0], 3, "uint8")
    o = oiio.ImageOutput.create(out)
    if o is None or not o.open(out, spec):
        sys.exit(f"cannot write {out}: {oiio.geterror()}")
    o.write_image(np.round(fig * 255).astype(np.uint8))
    o.close()
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
