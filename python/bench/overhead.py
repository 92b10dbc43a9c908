#!/usr/bin/env python3
"""Per-frame overhead of the deepsea Python module over the compositor's own time
(docs/python.md, "Overhead"). Renders the same in-memory RGB-D frame repeatedly and reports
medians: the wall time of Renderer.render() seen from Python, the compositor's own time inside
it (Renderer.timing["composite_s"]), and the overhead: the per-frame difference (array checks
and copies in, pybind11 dispatch, the dict of arrays out), of which "in module" is the part
inside the C++ call (Renderer.timing["call_s"] - composite_s).

    PYTHONPATH=build/python/module /usr/bin/python3 python/bench/overhead.py [--size 800]
"""

import argparse
import os
import statistics
import sys
import time

import numpy as np

import deepsea

SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def frame(size):
    """A textured tilted plane with a nearer box: uint8 sRGB colour, float32 planar depth."""
    v, u = np.mgrid[0:size, 0:size].astype(np.float32)
    x = (u - size / 2) / (0.75 * size)
    depth = 3.0 / (1.0 - 0.3 * x)
    depth[: size // 4, : size // 4] = 1.8
    rgb = np.empty((size, size, 3), np.uint8)
    rgb[..., 0] = np.where((u // 16 + v // 16) % 2, 200, 60)
    rgb[..., 1] = 120
    rgb[..., 2] = (40 + 150 * u / size).astype(np.uint8)
    return rgb, depth.astype(np.float32)


def measure(renderer, rgb, depth, repeats, **kw):
    wall, comp, call = [], [], []
    for i in range(repeats + 3):
        t0 = time.perf_counter()
        out = renderer.render(rgb, depth, **kw)
        t1 = time.perf_counter()
        del out  # as a data loader does: this frame's layers are gone before the next
        if i >= 3:  # warm-up: first frame of a size, buffer pool
            wall.append(t1 - t0)
            comp.append(renderer.timing["composite_s"])
            call.append(renderer.timing["call_s"])
    over = [w - c for w, c in zip(wall, comp)]
    inside = [c - k for c, k in zip(call, comp)]
    m = {k: statistics.median(v) * 1e3 for k, v in
         (("wall", wall), ("composite", comp), ("inside", inside), ("overhead", over))}
    m["min_composite"] = min(comp) * 1e3
    return m


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--size", type=int, default=800, help="frame width and height (pixels)")
    p.add_argument("--repeats", type=int, default=31, help="frames per case (median)")
    p.add_argument("--threads", type=int, default=0, help="worker threads (0: all cores)")
    p.add_argument("--asset", help="asset for a camera with this view (default: bake one)")
    a = p.parse_args()
    s = a.size
    if a.asset:
        asset = deepsea.load_asset(a.asset)
    else:
        # `deepsea bench`'s setup (volumes/demo.yaml: the authors' rig, deep:clear water,
        # forward scatter on), single scattering, at this size with the same view.
        demo = os.path.join(SRC, "volumes", "demo.yaml")
        camera = {"width": s, "height": s, "fx": 0.75 * s, "fy": 0.75 * s,
                  "cx": s / 2, "cy": s / 2}
        text = open(demo).read()
        text = text[text.index("rig:"):]  # rig and water; the camera is ours
        asset = deepsea.bake(text, camera=camera, xy_step=16, depth_samples=32, check=False)
    rgb, depth = frame(s)
    r = deepsea.Renderer(asset, threads=a.threads)
    print(f"{s}x{s}, {a.repeats} frames per case, threads {a.threads or os.cpu_count()}, "
          f"load average {os.getloadavg()[0]:.2f}")
    print(f"{'case':34s} {'wall ms':>8s} {'compositor ms':>14s} {'(min)':>7s} "
          f"{'overhead ms':>12s} {'in module':>10s} {'overhead':>9s}")
    cases = [("uint8 sRGB + float32 z, all layers", rgb, depth, {}),
             ("float32 linear + float32 z, all", rgb.astype(np.float32) / 255, depth, {"encoding": "linear"}),
             ("uint8 sRGB + float32 z, final only", rgb, depth, {"layers": "final"})]
    worst = 0.0
    for name, c, d, kw in cases:
        m = measure(r, c, d, a.repeats, **kw)
        ratio = m["overhead"] / m["composite"]
        worst = max(worst, ratio)
        print(f"{name:34s} {m['wall']:8.2f} {m['composite']:14.2f} {m['min_composite']:7.2f} "
              f"{m['overhead']:12.3f} {m['inside']:10.3f} {100 * ratio:8.2f}%")
    print(f"worst overhead: {100 * worst:.2f} % of the compositor's time")
    return 0


if __name__ == "__main__":
    sys.exit(main())
