#!/usr/bin/env python3
"""The forward layer of a validate.py row by a direct sum, apart from the runtime's blur
(docs/reference.md, "Where the forward layer's excess was").

Usage: forward_sum.py DEEPSEA WORK ROW [--step 4]
WORK is validate.py's (the row's setup.yaml, depth.exr, baked.exr = deepsea's layers, pt.exr =
the path tracer's; the asset beside them). For every `step`-th pixel it sums, over a frame three
times wider around the row's camera, the transport table's ring density (the asset's
`deepsea:forward_psf`, linear in depth, log-linear in angle between ring centres; the source
pixel's own disc by the enclosed share) times the source's radiance and solid angle, in four
ways: angle = pixel distance / fx and solid angle 1/fx^2 (the runtime's) or the true ones, and
the scene beyond the frame as its border pixels (the runtime's before its falloff) or lit as the
path tracer's plane is (`deepsea reference` single scattering over the wider frame, times the
in-frame ratio of deepsea's `direct` to it at the nearest border pixel). Inside the frame the
radiance is deepsea's `direct` times exp(c d). Prints each sum over the sampled pixels against
deepsea's and the path tracer's. Planes facing the camera only (the rows' scenes).
Debian's /usr/bin/python3 with numpy and OpenImageIO.
"""

import argparse
import json
import os
import re
import subprocess
import sys

import numpy as np

from compare_baked import oiio, read_layer, write_exr
from validate import ALBEDO, CI, TABLE, WATERS


def forward_table(asset):
    raw = open(asset, "rb").read()
    at = raw.index(b'{"depth":')
    t, _ = json.JSONDecoder().raw_decode(raw[at:].decode("latin-1"))
    return (np.array(t["depth"]), np.array(t["ring_edge"]),
            np.array(t["share"], dtype=float).reshape(len(t["depth"]), -1, 3))


class Table:
    def __init__(self, asset):
        self.depth, self.edge, share = forward_table(asset)
        omega = 2 * np.pi * (np.cos(self.edge[:-1]) - np.cos(self.edge[1:]))
        self.rho = share / omega[None, :, None]  # per steradian
        self.cum = np.concatenate([np.zeros((len(self.depth), 1, 3)), np.cumsum(share, 1)], 1)
        centre = np.sqrt(np.maximum(self.edge[:-1], 1e-6) * self.edge[1:])
        centre[0] = 0.5 * self.edge[1]
        self.log_centre = np.log(centre)

    def rows(self, d, arr):
        """arr (depths, ...) linear in depth at d (any shape), 0 at 0, the last beyond."""
        z = self.depth
        k = np.clip(np.searchsorted(z, d, side="right"), 1, len(z) - 1)
        f = np.clip((d - z[k - 1]) / (z[k] - z[k - 1]), 0, 1)[..., None, None]
        out = arr[k - 1] + f * (arr[k] - arr[k - 1])
        first = (d < z[0])[..., None, None]
        return np.where(first, arr[0] * (d / z[0])[..., None, None], out)

    def density(self, d, psi):
        rho = self.rows(d, self.rho).reshape(psi.size, -1, 3)
        lp = np.log(np.maximum(psi.ravel(), 1e-7))
        j = np.clip(np.searchsorted(self.log_centre, lp) - 1, 0, len(self.log_centre) - 2)
        t = np.clip((lp - self.log_centre[j]) / (self.log_centre[j + 1] - self.log_centre[j]),
                    0, 1)[:, None]
        i = np.arange(psi.size)
        a = np.log(np.maximum(rho[i, j], 1e-300))
        b = np.log(np.maximum(rho[i, j + 1], 1e-300))
        return np.exp(a + t * (b - a)).reshape(psi.shape + (3,))

    def within(self, d, psi):
        cum = self.rows(np.array([d]), self.cum)[0]
        return np.array([np.interp(psi, self.edge, cum[:, c]) for c in range(3)])


def gather(table, L, z, fx, cx, cy, sx, sy, exact, sub=4):
    """F at pixel (sx, sy) of the wide frame from radiance L (h, w, 3) on the plane z."""
    h, w = L.shape[:2]
    u, v = np.meshgrid(np.arange(w), np.arange(h))
    X, Y = (u - cx) / fx, (v - cy) / fx
    r = z * np.sqrt(1 + X * X + Y * Y)
    ray = np.stack([X, Y, np.ones_like(X)], -1) / np.sqrt(1 + X * X + Y * Y)[..., None]

    def angle(uu, vv):
        if not exact:
            return np.hypot(uu - sx, vv - sy) / fx
        q = np.stack([(uu - cx) / fx, (vv - cy) / fx, np.ones_like(uu, dtype=float)], -1)
        q /= np.linalg.norm(q, axis=-1)[..., None]
        return np.arccos(np.clip((q * ray[sy, sx]).sum(-1), -1, 1))

    omega = (1 / fx ** 2) / (1 + X * X + Y * Y) ** 1.5 if exact else np.full(X.shape, fx ** -2.0)
    psi = angle(u, v)
    weight = table.density(r * np.cos(psi), psi) * omega[..., None]
    near = (np.abs(u - sx) <= 2) & (np.abs(v - sy) <= 2)
    weight[near] = 0
    total = (weight * L).sum((0, 1))
    a = (np.arange(sub) + 0.5) / sub - 0.5
    for qy in range(sy - 2, sy + 3):
        for qx in range(sx - 2, sx + 3):
            if (qx, qy) == (sx, sy):  # the pixel's own disc: the enclosed share
                total += table.within(r[qy, qx], np.sqrt(omega[qy, qx] / np.pi)) * L[qy, qx]
                continue
            uu, vv = np.meshgrid(qx + a, qy + a)
            ps = angle(uu, vv)
            rho = table.density(r[qy, qx] * np.cos(ps), ps).reshape(-1, 3).mean(0)
            total += rho * omega[qy, qx] * L[qy, qx]
    return total


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("deepsea")
    ap.add_argument("work")
    ap.add_argument("row")
    ap.add_argument("--step", type=int, default=4)
    a = ap.parse_args()
    d = os.path.join(a.work, a.row)
    wname, rig, size, fov, _, _ = {**TABLE, **CI}[a.row]
    setup = open(os.path.join(d, "setup.yaml")).read()
    cam = dict(re.findall(r"(\w+): ([-0-9.e]+)", setup.split("\n")[0]))
    W, H, fx = int(cam["width"]), int(cam["height"]), float(cam["fx"])
    c = np.array(json.loads(re.search(r"attenuation: (\[.*\])", WATERS[wname]).group(1)))
    table = Table(os.path.join(a.work, f"{wname}_{rig}_{size}_{fov:g}.vdb"))
    z = float(oiio.ImageBuf(os.path.join(d, "depth.exr")).get_pixels(oiio.FLOAT)[0, 0, 0])
    # the wider frame: three times each side, the same pixels in its middle
    cx, cy = (3 * W - 1) / 2, (3 * H - 1) / 2
    files = {}
    for tag, (w, h, ccx, ccy) in {"wide": (3 * W, 3 * H, cx, cy),
                                  "narrow": (W, H, (W - 1) / 2, (H - 1) / 2)}.items():
        lines = setup.split("\n")
        lines[0] = (f"camera: {{width: {w}, height: {h}, fx: {fx!r}, fy: {fx!r}, "
                    f"cx: {ccx!r}, cy: {ccy!r}}}")
        cfg = os.path.join(d, f"sum_{tag}.yaml")
        open(cfg, "w").write("\n".join(lines))
        alb, dep = os.path.join(d, f"sum_{tag}_albedo.exr"), os.path.join(d, f"sum_{tag}_depth.exr")
        write_exr(alb, np.tile(np.array(ALBEDO, np.float32), (h, w, 1)))
        write_exr(dep, np.full((h, w, 1), z, np.float32))
        files[tag] = os.path.join(d, f"sum_{tag}_ss.exr")
        subprocess.run([a.deepsea, "reference", "--config", cfg, "--rgb", alb, "--depth", dep,
                        "--rel-tol", "1e-3", "--z-max", "20", "--layers", files[tag]],
                       check=True, stdout=subprocess.DEVNULL)
    direct = read_layer(os.path.join(d, "baked.exr"), "direct")
    ours = read_layer(os.path.join(d, "baked.exr"), "forward")
    pt = read_layer(os.path.join(d, "pt.exr"), "forward")
    ss_w, ss_n = read_layer(files["wide"], "direct"), read_layer(files["narrow"], "direct")

    def ranges(w, h, ccx, ccy):
        u, v = np.meshgrid(np.arange(w), np.arange(h))
        return z * np.sqrt(1 + ((u - ccx) / fx) ** 2 + ((v - ccy) / fx) ** 2)

    iy = np.clip(np.arange(3 * H) - H, 0, H - 1)
    ix = np.clip(np.arange(3 * W) - W, 0, W - 1)
    inside = direct * np.exp(c * ranges(W, H, (W - 1) / 2, (H - 1) / 2)[..., None])
    borders = inside[iy][:, ix]
    lit = ss_w * np.exp(c * ranges(3 * W, 3 * H, cx, cy)[..., None]) * (direct / ss_n)[iy][:, ix]
    lit[H:2 * H, W:2 * W] = inside
    ys, xs = np.arange(a.step // 2, H, a.step), np.arange(a.step // 2, W, a.step)
    o, p = ours[ys][:, xs].sum((0, 1)), pt[ys][:, xs].sum((0, 1))
    whole_ratio = ours.sum((0, 1)) / pt.sum((0, 1))
    print(f"{a.row}: {len(ys) * len(xs)} pixels; deepsea / path tracer "
          f"{np.round(o / p, 4)} (the whole image: {np.round(whole_ratio, 4)})")
    for name, L, exact in [("pixel angles, borders continued", borders, False),
                           ("pixel angles, lit beyond", lit, False),
                           ("true angles, borders continued", borders, True),
                           ("true angles, lit beyond", lit, True)]:
        s = sum(gather(table, L, z, fx, cx, cy, x + W, y + H, exact) for y in ys for x in xs)
        # against the path tracer through deepsea's whole image (the sampled pixels' own
        # path-traced sum is noisier)
        whole = s / o * whole_ratio
        print(f"  {name}: / deepsea {np.round(s / o, 4)}, / path tracer {np.round(s / p, 4)} "
              f"(through the whole image {np.round(whole, 4)})", flush=True)


if __name__ == "__main__":
    sys.exit(main())
