#!/usr/bin/env python3
"""A candidate for turbid-plane's `direct` layer low towards the image border (docs/validation.md): the lamp light that reaches the plane after scattering,
the path tracer's way (the plane is there: a path that meets it again stops and brings the
plane's reflected lamp light, albedo 0.55; no water beyond it) against the lamp field's (baked
in water without the plane). Green; cosine-weighted backward paths from the surface point in
infinite water, next events to the lamps at every scattering, one path set for both.

The reflected light is the plane's direct lamp light only; `scaled` multiplies it by the
point's own (direct + scattered) / direct, a rough allowance for the scattered lamp light the
plane reflects too.

    /usr/bin/python3 tools/reference/plane_return.py [PATHS]
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
N = int(sys.argv[1]) if len(sys.argv) > 1 else 20000
sys.argv = [sys.argv[0], "1", "turbid-plane"]  # oblique_forward's scene
import oblique_forward as of  # noqa: E402
c, b, g, Z, FX = of.c, of.b, of.g, of.Z, of.FX
a = c - b
rho = 0.55
def hgp(mu):
    return (1 - g*g) / (4*np.pi*(1 + g*g - 2*g*mu)**1.5)
def lamps_at(P, dback):
    """single-scattered lamp radiance toward -dback (the direction back along the path)"""
    out = np.zeros(len(P))
    for pos, axis, inten, sigma in of.LAMPS:
        L = P - np.array(pos); R = np.linalg.norm(L, axis=1); om = L / R[:, None]
        ax = np.array(axis) / np.linalg.norm(axis)
        th = np.arccos(np.clip(om @ ax, -1, 1))
        I = inten * np.exp(-0.5 * (th / np.radians(sigma))**2)
        out += I * np.exp(-c * R) / R**2 * hgp(np.sum(om * -dback, axis=1))
    return out
def Edirect(P):
    return of.lamp_radiance(FX * P[:, 0] / Z, FX * P[:, 1] / Z)
def run(x, seed):
    """One set of paths in infinite water; per path: everything (the lamp field's estimate), the
    plane's reflected direct light where the path first meets the plane again (the path
    tracer's), and what the path gathers after that (the lamp field's alone)."""
    rng = np.random.default_rng(seed)
    u1, u2 = rng.random(N), rng.random(N)
    st = np.sqrt(u1); ct = np.sqrt(1 - u1); ph = 2*np.pi*u2
    d = np.stack([st*np.cos(ph), st*np.sin(ph), -ct], 1)
    pos = np.tile(x, (N, 1)); w = np.ones(N); alive = np.ones(N, bool)
    tot = np.zeros(N); refl = np.zeros(N); after = np.zeros(N); crossed = np.zeros(N, bool)
    for k in range(300):
        idx = np.nonzero(alive)[0]
        if idx.size == 0: break
        s = rng.exponential(1/b, idx.size)
        if k > 0:
            dz = d[idx, 2]
            t = np.where(dz > 0, (Z - pos[idx, 2]) / np.where(dz > 0, dz, 1), np.inf)
            hit = (t <= s) & ~crossed[idx]
            hi = idx[hit]
            Ph = pos[hi] + d[hi] * t[hit][:, None]
            refl[hi] = w[hi] * np.exp(-a * t[hit]) * rho / np.pi * Edirect(Ph)
            crossed[hi] = True
        pos[idx] += d[idx] * s[:, None]
        w[idx] *= np.exp(-a * s)
        con = w[idx] * lamps_at(pos[idx], d[idx])
        tot[idx] += con
        after[idx] += np.where(crossed[idx], con, 0.0)
        d[idx] = of.hg(d[idx], rng)
        alive[idx[w[idx] < 1e-6]] = False
    diff = refl - after
    return (np.pi * tot.mean(), np.pi * diff.mean(), np.pi * diff.std() / np.sqrt(N),
            np.pi * refl.mean(), np.pi * after.mean())
for col, row in ((31, 23), (47, 23), (63, 23), (63, 47), (0, 23)):
    up, vp = col - 31.5, row - 23.5
    x = np.array([up / FX * Z, vp / FX * Z, Z])
    E0 = Edirect(x[None, :])[0]
    B, D, eD, R, F = run(x, 1)
    Ds = R * (E0 + B) / E0 - F
    print(f"pixel ({col},{row}): direct lamp E {E0:.5f}; scattered (infinite water) {B:.5f}; "
          f"with the plane minus without {D:+.5f} +- {eD:.5f} (returned by the water {R:.5f}, "
          f"gathered beyond the plane {F:.5f}); the lamp field's direct against the path tracer's "
          f"{-100 * D / (E0 + B + D):+.2f} +- {100 * eD / (E0 + B + D):.2f} %; scaled "
          f"{-100 * Ds / (E0 + B + Ds):+.2f} %", flush=True)
