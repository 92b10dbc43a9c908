#!/usr/bin/env python3
"""deepsea's baked multiple scattering against its own all-order path tracer (docs/reference.md).

Usage: compare_baked.py DEEPSEA WORK [--paths N] [--size 64x48] [--scenes clear-plane,...]
                        [--keep-reference]
Writes each scene's setup (YAML), albedo and depth (EXR) into WORK, runs
  deepsea bake --scattering multiple + deepsea render --layers   (the runtime)
  deepsea reference --scattering multiple --paths N              (the path tracer)
and prints, per layer and channel, the image sums and the 4x4-bin errors as a Markdown table.
Debian's /usr/bin/python3 with numpy and OpenImageIO.
"""

import argparse
import math
import os
import subprocess
import sys
import time

import numpy as np
import OpenImageIO as oiio

RIG = """rig:
  name: two-spots
  lights:
    - name: left
      position: [-0.5, 0.0, 0.0]
      direction: [0.510586, 0.0, 0.859826]
      intensity: [1.0, 0.9, 0.8]
      rid: {gaussian: {sigma_deg: 35}}
    - name: right
      position: [0.5, 0.0, 0.0]
      direction: [-0.510586, 0.0, 0.859826]
      intensity: [0.8, 0.9, 1.0]
      rid: {gaussian: {sigma_deg: 35}}
"""

# name: (water section, plane depth in metres or None for open water)
WATERS = {
    "clear": """water:
  name: clear
  attenuation: [0.4901, 0.1982, 0.1763]
  scattering: [0.1140, 0.1223, 0.1357]
  phase: {henyey_greenstein: {g: 0.9}}
  forward_scatter: on
""",
    "turbid": """water:
  name: turbid
  attenuation: [1.0, 0.95, 1.05]
  scattering: [0.8, 0.78, 0.82]
  phase: {henyey_greenstein: {g: 0.85}}
  forward_scatter: on
""",
}
SCENES = {"clear-plane": ("clear", 3.0), "turbid-plane": ("turbid", 2.0),
          "clear-empty": ("clear", None), "turbid-empty": ("turbid", None)}
ALBEDO = (0.7, 0.55, 0.4)
Z_MAX = 20.0  # open water ends here for both renderers


def write_exr(path, array):
    h, w = array.shape[:2]
    c = array.shape[2]
    spec = oiio.ImageSpec(w, h, c, oiio.FLOAT)
    out = oiio.ImageOutput.create(path)
    out.open(path, spec)
    out.write_image(np.ascontiguousarray(array, dtype=np.float32))
    out.close()


def read_layer(path, layer):
    buf = oiio.ImageBuf(path)
    names = buf.spec().channelnames
    idx = [names.index(f"{layer}.{c}") for c in "RGB"]
    return buf.get_pixels(oiio.FLOAT)[:, :, idx].astype(np.float64)


def run(cmd):
    t0 = time.time()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.time() - t0


def bins(img, b=4):
    h, w = img.shape[:2]
    return img[: h // b * b, : w // b * b].reshape(h // b, b, w // b, b, 3).sum(axis=(1, 3))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("deepsea")
    ap.add_argument("work")
    ap.add_argument("--paths", type=int, default=1024)
    ap.add_argument("--size", default="64x48")
    ap.add_argument("--scenes", default="clear-plane,turbid-plane")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--keep-reference", action="store_true",
                    help="reuse a scene's pt.exr already in WORK (same paths and seed)")
    a = ap.parse_args()
    w, h = map(int, a.size.split("x"))
    f = w / 48 * 38.0  # the Cycles scenes' 64.5 degree field of view
    os.makedirs(a.work, exist_ok=True)
    rows = []
    for scene in a.scenes.split(","):
        water, z = SCENES[scene]
        d = os.path.join(a.work, scene)
        os.makedirs(d, exist_ok=True)
        setup = os.path.join(d, "setup.yaml")
        with open(setup, "w") as fh:
            fh.write(f"camera: {{width: {w}, height: {h}, fx: {f}, fy: {f}, "
                     f"cx: {(w - 1) / 2}, cy: {(h - 1) / 2}}}\n" + RIG + WATERS[water])
        rgb, depth = os.path.join(d, "albedo.exr"), os.path.join(d, "depth.exr")
        write_exr(rgb, np.tile(np.array(ALBEDO, np.float32), (h, w, 1)))
        write_exr(depth, np.full((h, w, 1), z if z else np.inf, np.float32))
        asset = os.path.join(a.work, f"{water}.vdb")
        th = ["--threads", str(a.threads)]
        if not os.path.exists(asset):
            t = run([a.deepsea, "bake", "--config", setup, "--scattering", "multiple",
                     "--z-max", str(Z_MAX), "-o", asset] + th)
            print(f"{water}: bake {t:.1f} s", file=sys.stderr)
        baked, pt = os.path.join(d, "baked.exr"), os.path.join(d, "pt.exr")
        run([a.deepsea, "render", "--asset", asset, "--rgb", rgb, "--depth", depth,
             "--layers", baked] + th)
        if not (a.keep_reference and os.path.exists(pt)):
            t = run([a.deepsea, "reference", "--config", setup, "--rgb", rgb, "--depth", depth,
                     "--scattering", "multiple", "--paths", str(a.paths), "--z-max", str(Z_MAX),
                     "--layers", pt] + th)
            print(f"{scene}: path tracer {t:.1f} s ({a.paths} paths per pixel)", file=sys.stderr)
        layers = {"water": ["backscatter"], "surface": ["direct", "forward"],
                  "direct": ["direct"], "forward": ["forward"], "final": ["final"]}
        for name, parts in layers.items():
            if z is None and name != "water" and name != "final":
                continue
            ours = sum(read_layer(baked, p) for p in parts)
            ref = sum(read_layer(pt, p) for p in parts)
            # direct + forward: their variances added (the path-to-path correlation is left out)
            var = sum(read_layer(pt, p + "_se") ** 2 for p in parts)
            bo, br, bv = bins(ours), bins(ref), bins(var)
            for ch in range(3):
                so, sr, se = ours[:, :, ch].sum(), ref[:, :, ch].sum(), math.sqrt(var[:, :, ch].sum())
                rel = (bo[:, :, ch] - br[:, :, ch]) / br[:, :, ch]
                bse = np.sqrt(bv[:, :, ch]) / br[:, :, ch]
                rows.append((scene, name, "RGB"[ch], sr, 100 * se / sr, so, 100 * (so / sr - 1),
                             100 * np.abs(rel).max(), 100 * np.sqrt((rel ** 2).mean()),
                             100 * np.median(bse)))
    print(f"| scene | layer | ch | path tracer sum | SE | deepsea sum | diff | worst 4x4 bin "
          f"| rms bins | median bin SE |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]} | {r[2]} | {r[3]:.5g} | {r[4]:.2f}% | {r[5]:.5g} | "
              f"{r[6]:+.1f}% | {r[7]:.1f}% | {r[8]:.1f}% | {r[9]:.1f}% |")


if __name__ == "__main__":
    main()
