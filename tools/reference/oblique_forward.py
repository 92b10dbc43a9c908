#!/usr/bin/env python3
"""Why turbid-plane's and coastal-auv's forward layers are low towards the image border
(docs/validation.md): the forward light of a few pixels of
validate.py's row (turbid-plane: 64x48, 64.5 deg, plane at 2 m facing the camera, two spots;
coastal-auv: 160x120, plane at 3 m, the auv rig), green channel, three ways:

- pt: the path tracer's physics, a backward Monte Carlo from the camera along the pixel's ray
  to the plane as it is (z = Z, tilted to an off-axis ray), every order, scored where a
  scattered path first meets it;
- runtime: the transport table's model as the runtime applies it: planes facing the ray
  (forward_transport.h), a source at range r_q seen psi away weighed as the plane at depth
  r_q cos(psi), psi the pixel distance / fx (the blur shift-invariant in pixel space);
- true-angles: the same table with true angles and the true image position of each direction;
- runtime+lean, true-angles+lean: the two above with the kernel's lean on a surface tilted to
  the ray (optics/forward_lean.h): each source q weighed 1 - (rho - 1) (ln r(q) - ln r(p)), the
  range's change to first order, rho = 3/2;
- equidistant+lean: the runtime's blur in the equidistant image (forward_psf_warp.cpp): the
  pixel p moved to rho_p = fx atan(|p| / fx) along its radius, the source psi fx from there in
  the direction of the scattering, and back to the image by the inverse map, with the lean as
  runtime+lean (every scale warped here; the runtime keeps the narrowest in the image).

The table is Monte Carlo too (paths along the axis scored at 80 plane depths, linear in depth
between them). The surface radiance L_s: from the direct lamp light at the plane (Gaussian
RIDs, inverse square, incidence cosine, exp(-c R); no scattered lamp light), or from an EXR
render with --layers of the same scene on a frame with the same fx centred on the same axis
(direct / transmission), given as the third argument, or uniform (`uniform`). `bins8`: the
lamps' direct light at the centres of the lower-right quadrant's 8x8 bins instead of the pixels.

    /usr/bin/python3 tools/reference/oblique_forward.py PATHS [SCENE [WIDE.exr|uniform|bins8]]
"""
import sys

import numpy as np

# validate.py's rows, green: water (c, b, HG g), plane depth, width, height, lamps (position,
# axis, green intensity, sigma in degrees), the pixels to compute
SCENES = {
    "turbid-plane": ((0.95, 0.78, 0.85), 2.0, 64, 48,
                     (((-0.5, 0, 0), (0.510586, 0, 0.859826), 0.9, 35),
                      ((0.5, 0, 0), (-0.510586, 0, 0.859826), 0.9, 35)),
                     ((31, 23), (47, 23), (63, 23), (55, 40), (63, 47))),
    "coastal-auv": ((0.4, 0.3, 0.9), 3.0, 160, 120,
                    (((0, -0.7, -0.2), (0, 0.25, 1), 1.0, 20),
                     ((0.6, 0, 0), (-0.2, 0, 1), 0.8, 15)),
                    ((79, 59), (40, 30), (0, 59), (7, 7), (0, 0))),
}
scene = sys.argv[2] if len(sys.argv) > 2 else "turbid-plane"
(c, b, g), Z, WIDTH, HEIGHT, LAMPS, PIXELS = SCENES[scene]
FX = 0.5 * WIDTH / np.tan(np.radians(0.5 * 64.5))
RHO = 1.5  # the scattered light's mean arrival direction over its angle (forward_lean.h)


def hg(d, rng):
    n = d.shape[0]
    s = (1 - g * g) / (1 - g + 2 * g * rng.random(n))
    ct = np.clip((1 + g * g - s * s) / (2 * g), -1, 1)
    st = np.sqrt(1 - ct * ct)
    ph = 2 * np.pi * rng.random(n)
    a = np.where(np.abs(d[:, 0:1]) < 0.9, np.array([[1.0, 0, 0]]), np.array([[0.0, 1, 0]]))
    e1 = np.cross(d, a)
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    e2 = np.cross(d, e1)
    return ct[:, None] * d + (st * np.cos(ph))[:, None] * e1 + (st * np.sin(ph))[:, None] * e2


def run(v, depths, n, seed, max_order=400):
    """Backward paths from the camera along v (analog scattering, absorption as weight); for
    each plane z = depths[k] the first crossing of each scattered path: (k, X, Y, weight)."""
    rng = np.random.default_rng(seed)
    a = c - b
    pos = np.zeros((n, 3))
    d = np.tile(v, (n, 1))
    w = np.ones(n)
    alive = np.ones(n, bool)
    order = np.zeros(n, int)
    nxt = np.zeros(n, int)
    out = []
    K = len(depths)
    for _ in range(max_order):
        idx = np.nonzero(alive)[0]
        if idx.size == 0:
            break
        s = rng.exponential(1 / b, idx.size)
        p0, dd = pos[idx], d[idx]
        while True:
            j = nxt[idx]
            has = j < K
            zt = np.where(has, depths[np.minimum(j, K - 1)], np.inf)
            dz = dd[:, 2]
            t = np.where((dz > 0) & has, (zt - p0[:, 2]) / np.where(dz > 0, dz, 1), np.inf)
            cross = t <= s
            if not cross.any():
                break
            ci = np.nonzero(cross)[0]
            gi = idx[ci]
            sc = order[gi] > 0
            P = p0[ci] + dd[ci] * t[ci][:, None]
            out.append((j[ci][sc], P[sc, 0], P[sc, 1], (w[gi] * np.exp(-a * t[ci]))[sc]))
            nxt[gi] += 1
        done = nxt[idx] >= K
        alive[idx[done]] = False
        mi, sm = idx[~done], s[~done]
        pos[mi] += d[mi] * sm[:, None]
        w[mi] *= np.exp(-a * sm)
        order[mi] += 1
        d[mi] = hg(d[mi], rng)
        alive[mi[w[mi] < 1e-7]] = False
    return [np.concatenate([o[i] for o in out]) for i in range(4)]


def lamp_radiance(u, v):
    """Direct lamp irradiance at the plane point seen at image offsets (u, v) px (albedo out)."""
    P = np.stack([u / FX * Z, v / FX * Z, np.full_like(u, Z)], -1)
    E = np.zeros(u.shape)
    for pos, axis, inten, sigma in LAMPS:
        L = P - np.array(pos)
        R = np.linalg.norm(L, axis=-1)
        a = np.array(axis) / np.linalg.norm(axis)
        th = np.arccos(np.clip(L @ a / R, -1, 1))
        rid = np.exp(-0.5 * (th / np.radians(sigma)) ** 2)
        E += inten * rid * (L[..., 2] / R) / R**2 * np.exp(-c * R)
    return E


def main():
    n = int(sys.argv[1])
    pixels = PIXELS
    if len(sys.argv) > 3 and sys.argv[3] == "bins8":
        # the centres of the 8x8 bins of the lower-right quadrant (the rigs are mirror-symmetric
        # in green about the image's vertical axis; the two spots also about its horizontal)
        cx, cy = 0.5 * (WIDTH - 1), 0.5 * (HEIGHT - 1)
        pixels = [(cx + 4 + 8 * i, cy + 4 + 8 * j) for j in range(HEIGHT // 16)
                  for i in range(WIDTH // 16)]
    if len(sys.argv) > 3 and sys.argv[3] == "uniform":
        def Ls(u, v):
            return np.ones(np.shape(u))
    elif len(sys.argv) > 3 and sys.argv[3] != "bins8":
        import OpenImageIO as oiio
        buf = oiio.ImageBuf(sys.argv[3])
        names = buf.spec().channelnames
        px = buf.get_pixels(oiio.FLOAT)
        img = px[:, :, names.index("direct.G")] / px[:, :, names.index("transmission.G")]
        H, W = img.shape

        def Ls(u, v):
            iu = np.clip(np.rint(u + (W - 1) / 2).astype(np.int64), 0, W - 1)
            iv = np.clip(np.rint(v + (H - 1) / 2).astype(np.int64), 0, H - 1)
            return img[iv, iu]
    else:
        Ls = lamp_radiance

    def gather(u, v, w):
        ok = np.isfinite(u) & np.isfinite(v)
        return (w[ok] * Ls(u[ok], v[ok])).sum() / n

    def lean(u, v, w, up, vp):
        """Shares of the gathered light from more than 4 px towards the image centre and more
        than 4 px away from it (along the line through the centre; uniform surface)."""
        ok = np.isfinite(u) & np.isfinite(v)
        norm = np.hypot(up, vp)
        if norm == 0.0:
            return 0.0, 0.0
        t = -((u[ok] - up) * up + (v[ok] - vp) * vp) / norm
        return w[ok][t > 4].sum() / n, w[ok][t < -4].sum() / n

    depths = np.linspace(0.3, 4.0 * Z, 80)
    step = depths[1] - depths[0]
    k2, X2, Y2, W2 = run(np.array([0.0, 0.0, 1.0]), depths, n, 2)
    dk = depths[k2]
    norm = np.sqrt(X2**2 + Y2**2 + dk**2)
    ox, oy, oz = X2 / norm, Y2 / norm, dk / norm
    psi, phi = np.arccos(oz), np.arctan2(Y2, X2)
    for col, row in pixels:
        up, vp = col - 0.5 * (WIDTH - 1), row - 0.5 * (HEIGHT - 1)
        v = np.array([up, vp, FX])
        v /= np.linalg.norm(v)
        _, X, Y, Wt = run(v, np.array([Z]), n, 1)
        f_pt = gather(FX * X / Z, FX * Y / Z, Wt)
        du, dv = FX * psi * np.cos(phi), FX * psi * np.sin(phi)
        rq = Z * np.sqrt(1 + ((up + du) ** 2 + (vp + dv) ** 2) / FX**2)
        hat = np.clip(1 - np.abs(rq * oz - dk) / step, 0, 1)
        f_rt = gather(up + du, vp + dv, hat * W2)
        e1 = np.cross(v, [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(v, e1)
        om = ox[:, None] * e1 + oy[:, None] * e2 + oz[:, None] * v
        front = om[:, 2] > 1e-6
        omz = np.where(front, om[:, 2], 1.0)
        hat3 = np.where(front, np.clip(1 - np.abs(Z / omz * oz - dk) / step, 0, 1), 0)
        uu = np.where(front, FX * om[:, 0] / omz, np.inf)
        vv = np.where(front, FX * om[:, 1] / omz, np.inf)
        f_ta = gather(uu, vv, hat3 * W2)
        # the lean: ln r of the plane z = Z to first order about the pixel's ray, in pixels for
        # the runtime (its gradient x / |v|^2 per unit of x = u / fx), along the gnomonic
        # offset for true angles
        x, y = up / FX, vp / FX
        v2 = 1.0 + x * x + y * y
        lean_rt = 1.0 + (RHO - 1.0) * (-(x * du + y * dv) / (FX * v2))
        ow = om / np.where(front, om @ v, 1.0)[:, None]
        lean_ta = np.where(front, 1.0 + (RHO - 1.0) * (ow[:, 2] - v[2]) / v[2], 0.0)
        f_rl = gather(up + du, vp + dv, hat * W2 * np.clip(lean_rt, 0, None))
        # the equidistant image: radius fx atan(r / fx), the table's angle psi at psi fx there
        rp = np.hypot(up, vp)
        sp = np.arctan(rp / FX) * FX / rp if rp > 0 else 1.0
        eu, ev = sp * up + du, sp * vp + dv
        th = np.hypot(eu, ev) / FX
        inside = th < 0.5 * np.pi - 1e-6
        back = np.where(inside & (th > 0), np.tan(np.minimum(th, 1.5)) / np.maximum(th, 1e-12), 1.0)
        qu, qv = np.where(inside, eu * back, np.inf), np.where(inside, ev * back, np.inf)
        rqe = Z * np.sqrt(1 + (np.where(inside, qu, 0) ** 2 + np.where(inside, qv, 0) ** 2) / FX**2)
        hate = np.where(inside, np.clip(1 - np.abs(rqe * oz - dk) / step, 0, 1), 0)
        lean_eq = 1.0 + (RHO - 1.0) * (-(x * (qu - up) + y * (qv - vp)) / (FX * v2))
        f_el = gather(qu, qv, hate * W2 * np.clip(np.where(inside, lean_eq, 0), 0, None))
        f_tl = gather(uu, vv, hat3 * W2 * np.clip(lean_ta, 0, None))
        lp = Ls(np.array([up]), np.array([vp]))[0]
        leans = (lean(FX * X / Z, FX * Y / Z, Wt, up, vp), lean(up + du, vp + dv, hat * W2, up, vp),
                 lean(uu, vv, hat3 * W2, up, vp))
        off = np.degrees(np.arctan(np.hypot(up, vp) / FX))
        print(f"pixel ({col:g},{row:g}) {off:4.1f} deg: forward / L_s: pt {f_pt / lp:.4f}, "
              f"runtime {f_rt / lp:.4f} ({100 * (f_rt / f_pt - 1):+.1f} %), "
              f"true-angles {f_ta / lp:.4f} ({100 * (f_ta / f_pt - 1):+.1f} %); with the lean: "
              f"runtime {100 * (f_rl / f_pt - 1):+.1f} %, true-angles {100 * (f_tl / f_pt - 1):+.1f} %, "
              f"equidistant {100 * (f_el / f_pt - 1):+.1f} %"
              f"; shares from > 4 px "
              f"towards / away from the centre: " +
              ", ".join(f"{a:.3f} / {o:.3f}" for a, o in leans), flush=True)


if __name__ == "__main__":
    main()
