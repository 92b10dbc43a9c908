#!/usr/bin/env python3
"""Pools path-traced layer files of one scene traced with different seeds (docs/validation.md).

Usage: combine_traces.py OUT.exr FULL.exr [IN.exr[@ROW,COLUMN] ...]
FULL.exr and each IN.exr are `deepsea reference --scattering multiple --layers` of the same
setup, albedo and depth, each with its own --seed; IN.exr@ROW,COLUMN is a window of the camera
whose pixel (0, 0) is FULL's pixel (COLUMN, ROW), traced with the same rays (validate.py's
camera(window=...)). The path tracer seeds each path from (seed, pixel, path index), so traces
with different seeds are independent, and pooling them is one trace with all their paths: a
long trace can run as windows or chunks that each finish on a loaded machine, and be pooled.
Per pixel, over the traces that cover it, with n_i paths, mean m_i and standard error s_i:
  mean = sum n_i m_i / N,  standard error = sqrt(sum n_i^2 s_i^2) / N,  N = sum n_i.
The geometric layers (depth, normal, transmission) are FULL's. Also writes the layer `paths`
(N per pixel, in all three channels). Debian's /usr/bin/python3 with numpy and OpenImageIO.
"""

import sys

import numpy as np
import OpenImageIO as oiio

MC = ("direct", "forward", "backscatter", "final")  # the layers that carry a standard error


def read(arg):
    path, _, at = arg.partition("@")
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    meta = {a.name: a.value for a in spec.extra_attribs}
    r, c = (int(x) for x in at.split(",")) if at else (0, 0)
    return path, spec, meta, buf.get_pixels(oiio.FLOAT).astype(np.float64), r, c


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out = sys.argv[1]
    traces = [read(a) for a in sys.argv[2:]]
    _, spec0, _, full, _, _ = traces[0]
    names = list(spec0.channelnames)
    seeds = [t[2].get("deepsea:seed") for t in traces]
    if len(set(seeds)) != len(seeds):
        sys.exit(f"traces share a seed ({seeds}): they are not independent")
    h, w = full.shape[:2]
    n_px = np.zeros((h, w))
    mean = np.zeros_like(full)
    var = np.zeros_like(full)
    se_of = {}  # channel index of a Monte Carlo channel -> its standard error's channel index
    for ci, name in enumerate(names):
        layer, _, chan = name.partition(".")
        if layer in MC:
            se_of[ci] = names.index(f"{layer}_se.{chan}")
    for path, spec, meta, px, r, c in traces:
        th, tw = px.shape[:2]
        if list(spec.channelnames) != names or r < 0 or c < 0 or r + th > h or c + tw > w:
            sys.exit(f"{path}: other channels than {traces[0][0]}, or not inside it")
        n = float(meta["deepsea:paths"])
        win = (slice(r, r + th), slice(c, c + tw))
        n_px[win] += n
        for ci, si in se_of.items():
            mean[win + (ci,)] += n * px[:, :, ci]
            var[win + (si,)] += (n * px[:, :, si]) ** 2
    acc = full.copy()
    for ci, si in se_of.items():
        acc[:, :, ci] = mean[:, :, ci] / n_px
        acc[:, :, si] = np.sqrt(var[:, :, si]) / n_px
    acc = np.concatenate([acc, np.repeat(n_px[:, :, None], 3, axis=2)], axis=2)
    spec = oiio.ImageSpec(w, h, len(names) + 3, oiio.FLOAT)
    for a in spec0.extra_attribs:
        spec.attribute(a.name, a.type, a.value)
    spec.channelnames = tuple(names + ["paths.R", "paths.G", "paths.B"])
    spec.attribute("deepsea:paths", f"{int(n_px.min())}..{int(n_px.max())}")
    spec.attribute("deepsea:seed", ",".join(str(s) for s in seeds))
    o = oiio.ImageOutput.create(out)
    o.open(out, spec)
    o.write_image(acc.astype(np.float32))
    o.close()
    print(f"{out}: {len(traces)} traces, {int(n_px.min())}..{int(n_px.max())} paths per pixel")


if __name__ == "__main__":
    main()
